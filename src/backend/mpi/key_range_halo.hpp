// Decomposition of the particles across MPI ranks by ranges of the cell key
// (core/cell_key.hpp; private header).
//
// The CPU solver sorts its particles by cell key, so a range of keys is,
// after the sort, a range of particle indices. Rank r owns the cells whose
// keys lie in [cut(r), cut(r + 1)): the particles whose x* (after prediction
// and the swept collision, the positions the sort uses) lie there. Ranges
// follow the Morton curve over the key's bricks, so each is a compact region
// (not a slab of whole planes: no limit of one rank per plane). Every step:
//
//   distribute  when the ranks' particle counts differ by more than 5 %, the
//               cuts move to balance them (a sparse histogram of the key's
//               64-cell rows gathered from all ranks); particles whose cell another
//               rank owns go to it (migration, MPI_Alltoallv); the owned
//               particles whose cell has a neighbour cell another rank owns
//               go to that rank as ghosts (every neighbour of an owned
//               particle is then owned or a ghost)
//   (the solver sorts by cell key: the owned particles are one range)
//   exchange    after each pass whose results neighbours read (lambda and
//               density, corrected x*, vorticity, the curvature force's
//               fields) the ghosts' values are replaced by their owners'
//               (MPI_Alltoallv of the values, in sorted order on both sides)
//   collect     the ghosts are dropped
//
// Bit-identity with one process: the solver's results for a particle depend
// on its neighbour list, a list of particles in memory order (the SIMD lanes
// a neighbour falls into depend on its position in the list). The one-process
// memory order is a stable sort by cell key of the previous step's order, i.e.
// a total order of all particles. Each particle carries its place in that
// order (its key: the previous order's global index), and distribute puts
// the store in that order before the sort, so a rank's sorted store is the
// one-process order restricted to its particles and every owned particle's
// neighbour list holds the same particles in the same order. Ghost values
// are their owners' values. Hence N ranks compute the same bits as one, for
// any cuts. The ranks' key ranges are in rank order, so the owned particles
// of ranks 0, 1, ... after the step are the one-process order.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "backend/cpu/solver.hpp"
#include "backend/mpi/particle_record.hpp"

namespace pbf {

// Throws std::runtime_error naming `call` when an MPI call failed.
void checkMpi(int code, const char* call);

class KeyRangeHalo {
  public:
    // `search`: the solver's neighbour search (its cell frame and, during a
    // step, the sorted keys).
    KeyRangeHalo(MPI_Comm comm, const NeighborSearch& search);
    KeyRangeHalo(const KeyRangeHalo&) = delete;
    KeyRangeHalo& operator=(const KeyRangeHalo&) = delete;
    ~KeyRangeHalo();

    MPI_Datatype recordType() const { return recordType_; }
    // Rank r owns the cell keys [cuts()[r], cuts()[r + 1]).
    const std::vector<std::uint64_t>& cuts() const { return cuts_; }
    int ownerOf(const Vec3& x) const;
    int ownerOfKey(std::uint64_t cellKey) const;
    // Cuts into equal shares of all ranks' particles (collective: each
    // gives its own); every rank gets the same cuts.
    void cutFor(const ParticleStore& particles);
    // Sends each particle to the rank that owns its cell (by x*); the store
    // and `keys` (its particles' places in a total order, increasing) are
    // replaced by this rank's, in key order.
    void migrate(ParticleStore& p, std::vector<std::uint64_t>& keys);
    // Frees the per-step scratch (after a migration of all particles, whose
    // buffers a step's few migrants and ghosts do not need).
    void releaseScratch();
    long long rebalances() const { return rebalances_; }

    // The keys of the store's particles, in store order, increasing (the
    // backend keeps them; distribute reads them).
    void setKeys(const std::vector<std::uint64_t>* keys) { keys_ = keys; }

    // After prediction and the swept collision: balance, migration, arrivals
    // and ghosts added, the store put in key order (see above).
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

    // The last step's ghosts, the ranks it exchanged them with, and the bytes
    // this rank sent in it.
    std::uint64_t ghosts() const { return ghostsReceived_; }
    std::uint64_t peers() const;
    std::uint64_t bytesSent() const { return bytesSent_; }

  private:
    struct Entry {
        std::uint64_t key;
        std::uint32_t source;  // < old size: index in the old store; else incoming_[source - old]
    };
    template <class T>
    void exchangeBytes(T* data, std::size_t bytes);
    void mergeRun(std::size_t runBegin);
    // The migration of distribute and migrate: entries_ and incoming_ hold
    // this rank's particles (by the cell keys in cellKeys_) in key order.
    void migrateEntries(const ParticleStore& p, const std::vector<std::uint64_t>& keys);
    std::size_t exchangeRecords(std::size_t storeSize, const char* what);
    void rebuild(ParticleStore& p);
    // The count of all ranks' particles per block of cells (sorted blocks).
    void globalHistogram(const std::vector<std::uint64_t>& cellKeys,
                         std::vector<std::uint64_t>& keys,
                         std::vector<std::uint64_t>& counts) const;
    // The ranks other than this one that own a neighbour cell of `cellKey`,
    // in increasing order, into peers_ (cached for the last key asked).
    const std::vector<int>& peersOf(std::uint64_t cellKey);
    // Cuts for a global histogram of (block key, particles), sorted by key;
    // also the busiest rank's share under them.
    std::vector<std::uint64_t> cutsFor(const std::vector<std::uint64_t>& blocks,
                                       const std::vector<std::uint64_t>& counts) const;
    void rebalance(const std::vector<std::uint64_t>& cellKeys);
    void adoptCuts(std::vector<std::uint64_t> cuts);

    MPI_Comm comm_;
    int rank_ = 0;
    int ranks_ = 1;
    MPI_Datatype recordType_;
    const NeighborSearch& search_;
    std::vector<std::uint64_t> cuts_;
    std::uint64_t lo_ = 0, hi_ = 0;  // this rank's keys
    double balancedRatio_ = 1.0;     // busiest / mean the current cuts were made for
    long long rebalances_ = 0;
    const std::vector<std::uint64_t>* keys_ = nullptr;

    // Per step (scratch kept between steps: no allocation once sizes settle).
    std::vector<std::uint64_t> cellKeys_;
    std::vector<Entry> entries_;
    std::vector<ParticleRecord> outgoing_, incoming_;
    std::vector<std::pair<std::uint32_t, int>> ghostPairs_;  // (entry, rank) of each ghost sent
    std::vector<int> sendCounts_, receiveCounts_, sendOffsets_, receiveOffsets_;
    std::uint64_t peersKey_ = ~std::uint64_t{0};
    std::vector<int> peers_;
    // After the sort: the owned particles [begin_, end_); for each rank, the
    // store indices whose values it gets from this one (sendIndex_) and those
    // this one gets from it (receiveIndex_), both in store order.
    std::size_t begin_ = 0, end_ = 0, ghostsReceived_ = 0;
    std::uint64_t bytesSent_ = 0;
    std::vector<std::vector<std::uint32_t>> sendIndex_, receiveIndex_;
    std::vector<std::byte> sendBuffer_, receiveBuffer_;
    std::vector<int> sendBytes_, receiveBytes_, sendByteOffsets_, receiveByteOffsets_;
};

}  // namespace pbf
