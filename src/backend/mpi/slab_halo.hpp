// Slab decomposition of the sorted grid across MPI ranks (private header).
//
// The CPU solver numbers grid cells with the domain's longest axis slowest,
// so a range of planes of cells across that axis is a range of cell indices
// and, after the counting sort, a range of particle indices. Rank r owns the
// planes [cut(r), cut(r + 1)): the particles whose x* (after prediction and
// the swept collision, the positions the sort uses) lie there. Every step:
//
//   distribute  re-cut the slabs by particle counts (dynamic load balance,
//               a histogram of planes summed over ranks); particles whose
//               plane another rank owns go to it (migration, MPI_Alltoallv);
//               the owned particles of the border planes go to the
//               neighbouring ranks as ghosts (one plane = one kernel radius:
//               every neighbour of an owned particle is owned or a ghost)
//   (the solver sorts by cell: ghosts from below, owned, ghosts from above)
//   exchange    after each pass whose results neighbours read (lambda and
//               density, corrected x*, vorticity) the ghosts' values are
//               replaced by their owners' (MPI_Sendrecv with each neighbour
//               rank; the ranges are contiguous on both sides)
//   collect     the ghosts are dropped
//
// Bit-identity with one process: the solver's results for a particle depend
// on its neighbour list, a list of particles in memory order (the SIMD lanes
// a neighbour falls into depend on its position in the list). The one-process
// memory order is a stable sort by cell of the previous step's order, i.e. a
// total order of all particles. Each particle carries its place in that
// order (its key: the previous order's global index), and distribute puts
// the store in key order before the sort, so a rank's sorted store is the
// one-process order restricted to its particles and every owned particle's
// neighbour list holds the same particles in the same order. Ghost values
// are their owners' values. Hence N ranks compute the same bits as one.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "backend/cpu/solver.hpp"
#include "backend/mpi/particle_record.hpp"

namespace pbf {

// Throws std::runtime_error naming `call` when an MPI call failed.
void checkMpi(int code, const char* call);

class SlabHalo {
  public:
    // `grid`: the solver's neighbour search (geometry and, during a step,
    // the sorted cell ranges). Throws std::runtime_error when the grid has
    // fewer planes than there are ranks.
    SlabHalo(MPI_Comm comm, const NeighborSearch& grid);
    SlabHalo(const SlabHalo&) = delete;
    SlabHalo& operator=(const SlabHalo&) = delete;
    ~SlabHalo();

    MPI_Datatype recordType() const { return recordType_; }
    // Rank r owns planes [cuts()[r], cuts()[r + 1]).
    const std::vector<std::uint32_t>& cuts() const { return cuts_; }
    int ownerOf(const Vec3& x) const;
    // Cuts the slabs for this global histogram of particles per plane:
    // always with `force`, else only when the current cut's busiest rank has
    // more than 5 % more particles than the new cut's would (no churn).
    void balance(const std::vector<std::uint64_t>& planeCounts, bool force);
    long long rebalances() const { return rebalances_; }

    // The keys of the store's particles, in store order, increasing (the
    // backend keeps them; distribute reads them).
    void setKeys(const std::vector<std::uint64_t>* keys) { keys_ = keys; }

    // After prediction and the swept collision: migration, arrivals and
    // ghosts added, the store put in key order (see above).
    void distribute(ParticleStore& p);
    // After the sort: the owned particles are [begin, end) of the store.
    void ownedRange(const NeighborSearch& search, std::size_t& begin, std::size_t& end);
    // The ghosts' entries of these arrays (store order) from their owners.
    void exchange(PackedPoint* records);
    void exchange(float* values);
    void exchange(Float3Array& values);
    // Sums over all processes, in place (integers: exact in any order).
    void sum(std::int64_t* values, int count);
    // End of the step: drops the ghosts.
    void collect(ParticleStore& p);

  private:
    struct Entry {
        std::uint64_t key;
        std::uint32_t source;  // < old size: index in the old store; else incoming_[source - old]
    };
    template <class T>
    void exchangeBytes(T* data, std::size_t bytes);
    void mergeRun(std::size_t runBegin);
    std::vector<std::uint32_t> cutsFor(const std::vector<std::uint64_t>& counts) const;

    MPI_Comm comm_;
    int rank_ = 0;
    int ranks_ = 1;
    MPI_Datatype recordType_;
    const NeighborSearch& grid_;
    std::vector<std::uint32_t> cuts_;
    std::uint32_t lo_ = 0, hi_ = 0;  // this rank's planes
    long long rebalances_ = 0;
    const std::vector<std::uint64_t>* keys_ = nullptr;

    // Per step (scratch kept between steps: no allocation once sizes settle).
    std::vector<std::uint32_t> planes_;
    std::vector<std::uint64_t> histogram_;
    std::vector<Entry> entries_;
    std::vector<ParticleRecord> outgoing_, incoming_, ghostsDown_, ghostsUp_;
    std::vector<int> sendCounts_, receiveCounts_, sendOffsets_, receiveOffsets_;
    ParticleStore next_;
    // After the sort: ghosts [0, begin_) from rank - 1 and [end_, size_) from
    // rank + 1; this rank's first and last planes [begin_, downEnd_) and
    // [upBegin_, end_) are the ghosts of rank - 1 and rank + 1.
    std::size_t size_ = 0, begin_ = 0, end_ = 0, downEnd_ = 0, upBegin_ = 0;
    std::size_t ghostsBelow_ = 0, ghostsAbove_ = 0;
};

}  // namespace pbf
