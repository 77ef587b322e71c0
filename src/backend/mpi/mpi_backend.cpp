// The distributed backend: each MPI rank runs the CPU backend's solver on
// its range of cell keys (backend/mpi/key_range_halo.hpp) and answers the World's
// reductions with global reductions. Scene set-up (solids, emitters, rigid
// bodies) is replicated on every rank by the World. Each rank gives its part
// of the one-process memory order (downloadPart) to the files all ranks
// write at once (PLY, H5Part, checkpoints); download() gathers the ranges
// on rank 0 in rank order, the one-process memory order (VTK, pictures).
#include "backend/mpi/mpi_backend.hpp"

#include <mpi.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

#include "backend/cpu/solver.hpp"
#include "backend/mpi/key_range_halo.hpp"
#include "backend/outlets.hpp"
#include "backend/reactions.hpp"

namespace pbf {
namespace {

// Sums in rank order on every rank (all ranks get the same bits, whatever
// algorithm the MPI library picks for a reduction).
std::vector<double> sumOverRanks(MPI_Comm comm, const std::vector<double>& mine, int ranks) {
    std::vector<double> all(mine.size() * std::size_t(ranks));
    checkMpi(MPI_Allgather(mine.data(), int(mine.size()), MPI_DOUBLE, all.data(), int(mine.size()),
                           MPI_DOUBLE, comm),
             "MPI_Allgather (sums)");
    std::vector<double> total(mine.size(), 0.0);
    for (int r = 0; r < ranks; ++r)
        for (std::size_t k = 0; k < mine.size(); ++k)
            total[k] += all[std::size_t(r) * mine.size() + k];
    return total;
}

class MpiBackend final : public Backend {
  public:
    MpiBackend(const SimulationParams& params, const BackendOptions& options)
        : solver_(params.domain, params.kernelRadius(), options.compactListSpan),
          halo_(MPI_COMM_WORLD, solver_.neighborSearch()) {
        MPI_Comm_rank(comm_, &rank_);
        MPI_Comm_size(comm_, &ranks_);
        halo_.setKeys(&keys_);
        insertExchanges(solver_.plan());
    }

    BackendKind kind() const override { return BackendKind::Mpi; }
    std::size_t size() const override { return std::size_t(total_); }

    // Every rank is handed the same particles (the World's emitters run on
    // every rank); each keeps those in its key range and counts the ids of all.
    void append(std::span<const Vec3> positions, std::span<const Vec3> velocities,
                float density) override {
        if (positions.size() != velocities.size())
            throw std::invalid_argument(
                "Backend::append: positions and velocities differ in length");
        checkParticlesPerProcess(kind(), store_.size(), positions.size());
        for (std::size_t k = 0; k < positions.size(); ++k) {
            if (halo_.ownerOf(positions[k]) == rank_) {
                store_.add(positions[k], velocities[k], density);
                keys_.push_back(nextKey_ + k);  // after every particle there is: appended last
            } else {
                store_.setNextId(store_.nextId() + 1);
            }
        }
        total_ += positions.size();
        nextKey_ += positions.size();
    }

    // Each rank removes its own particles in the outlets; the rest keep
    // their order (a stable compaction, as one process's), and their keys
    // close the gaps: a key drops by the removed particles with smaller keys
    // on every rank, so the keys stay the places [0, total) of one order.
    std::size_t removeInside(std::span<const OutletRegion> outlets) override {
        if (outlets.empty()) return 0;
        std::vector<std::uint64_t> gone;
        if (const auto kept = detail::particlesOutside(store_, outlets)) {
            std::size_t next = 0;
            for (std::size_t i = 0; i < store_.size(); ++i) {
                if (next < kept->size() && (*kept)[next] == i)
                    keys_[next++] = keys_[i];
                else
                    gone.push_back(keys_[i]);
            }
            keys_.resize(kept->size());
            store_.keepOnly(*kept);
        }
        int mine = int(gone.size());
        std::vector<int> counts(static_cast<std::size_t>(ranks_)),
            offsets(static_cast<std::size_t>(ranks_), 0);
        checkMpi(MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_),
                 "MPI_Allgather (removed particles)");
        for (int r = 1; r < ranks_; ++r)
            offsets[std::size_t(r)] = offsets[std::size_t(r - 1)] + counts[std::size_t(r - 1)];
        std::vector<std::uint64_t> removed(std::size_t(offsets.back() + counts.back()));
        checkMpi(MPI_Allgatherv(gone.data(), mine, MPI_UINT64_T, removed.data(), counts.data(),
                                offsets.data(), MPI_UINT64_T, comm_),
                 "MPI_Allgatherv (removed particles)");
        if (removed.empty()) return 0;
        std::sort(removed.begin(), removed.end());
        for (std::uint64_t& key : keys_)
            key -= std::uint64_t(std::lower_bound(removed.begin(), removed.end(), key) -
                                 removed.begin());
        total_ -= removed.size();
        nextKey_ = total_;
        updateOffset();
        return removed.size();
    }

    void driveInside(std::span<const InletBuffer> buffers) override {
        detail::driveInside(store_, buffers);
    }

    void step(const SolverContext& context, float dt) override {
        reactions_.reset(store_.size(), context.solids);
        solver_.step(context, store_, dt, times_, reactions_.active() ? &reactions_ : nullptr);
        renumber();
        // The coupled solids' reactions: this rank's share, summed over ranks.
        reactions_.forces(context.constants.particleMass, dt, lastReactions_);
        if (!lastReactions_.empty()) {
            std::vector<double> mine;
            for (const SolidReaction& r : lastReactions_)
                for (const Vec3& v : {r.force, r.torque})
                    mine.insert(mine.end(), {double(v.x), double(v.y), double(v.z)});
            const std::vector<double> total = sumOverRanks(comm_, mine, ranks_);
            for (std::size_t s = 0; s < lastReactions_.size(); ++s) {
                const double* t = total.data() + 6 * s;
                lastReactions_[s].force = {float(t[0]), float(t[1]), float(t[2])};
                lastReactions_[s].torque = {float(t[3]), float(t[4]), float(t[5])};
            }
        }
    }
    const StageTimes& lastStageTimes() const override { return times_; }
    std::span<const SolidReaction> lastReactions() const override { return lastReactions_; }

    float maxSpeed() const override {
        float speed = pbf::maxSpeed(store_);
        checkMpi(MPI_Allreduce(MPI_IN_PLACE, &speed, 1, MPI_FLOAT, MPI_MAX, comm_),
                 "MPI_Allreduce (largest speed)");
        return speed;
    }

    // The first bad particle in the one-process memory order: the lowest
    // rank that has one, its lowest index.
    std::optional<BadParticle> findBadParticle(double speedLimit) const override {
        const std::optional<BadParticle> mine = pbf::findBadParticle(store_, speedLimit);
        int has = mine ? 1 : 0;
        std::vector<int> all(static_cast<std::size_t>(ranks_), 0);
        checkMpi(MPI_Allgather(&has, 1, MPI_INT, all.data(), 1, MPI_INT, comm_),
                 "MPI_Allgather (state guard)");
        const auto first = std::find(all.begin(), all.end(), 1);
        if (first == all.end()) return std::nullopt;
        const int root = int(first - all.begin());
        BadParticle bad = mine.value_or(BadParticle{});
        std::uint64_t where[2] = {std::uint64_t(offset_ + bad.index), bad.id};
        float values[6] = {bad.position.x, bad.position.y, bad.position.z,
                           bad.velocity.x, bad.velocity.y, bad.velocity.z};
        checkMpi(MPI_Bcast(where, 2, MPI_UINT64_T, root, comm_), "MPI_Bcast (state guard)");
        checkMpi(MPI_Bcast(values, 6, MPI_FLOAT, root, comm_), "MPI_Bcast (state guard)");
        int length = int(bad.problem.size());
        checkMpi(MPI_Bcast(&length, 1, MPI_INT, root, comm_), "MPI_Bcast (state guard)");
        bad.problem.resize(std::size_t(length));
        checkMpi(MPI_Bcast(bad.problem.data(), length, MPI_CHAR, root, comm_),
                 "MPI_Bcast (state guard)");
        bad.index = std::size_t(where[0]);
        bad.id = where[1];
        bad.position = {values[0], values[1], values[2]};
        bad.velocity = {values[3], values[4], values[5]};
        return bad;
    }

    StateStatistics statistics(const SolverContext& context) const override {
        const StateStatistics s =
            computeStatistics(store_, context.constants, context.params.domain, context.solids,
                              context.params.particleRadius);
        const std::vector<double> sums = sumOverRanks(
            comm_,
            {double(s.particles), s.averageDensityError * double(s.particles), s.kineticEnergy,
             s.momentum.x, s.momentum.y, s.momentum.z, double(s.escaped), double(s.insideSolid)},
            ranks_);
        double maxima[2] = {s.maxDensityError, s.maxSpeed};
        checkMpi(MPI_Allreduce(MPI_IN_PLACE, maxima, 2, MPI_DOUBLE, MPI_MAX, comm_),
                 "MPI_Allreduce (statistics)");
        StateStatistics total;
        total.particles = std::size_t(sums[0]);
        total.averageDensityError = sums[0] > 0.0 ? sums[1] / sums[0] : 0.0;
        total.kineticEnergy = sums[2];
        total.momentum = {float(sums[3]), float(sums[4]), float(sums[5])};
        total.escaped = std::size_t(sums[6]);
        total.insideSolid = std::size_t(sums[7]);
        total.maxDensityError = maxima[0];
        total.maxSpeed = maxima[1];
        return total;
    }

    const ParticleStore* hostState() const override { return nullptr; }
    ParticleStore* mutableHostState() override { return nullptr; }

    // Gathers the ranges on rank 0 in rank order (the one-process memory
    // order); the other ranks get no particles.
    void download(ParticleStore& out) const override {
        std::vector<ParticleRecord> mine(store_.size());
        for (std::size_t i = 0; i < store_.size(); ++i) mine[i] = recordOf(store_, i, keys_[i]);
        // The optional fields (the warm start's accelerations) are kept by
        // every rank that has particles while they are on (a rank may have none).
        std::uint32_t optional = store_.keptOptionalFields();
        checkMpi(MPI_Allreduce(MPI_IN_PLACE, &optional, 1, MPI_UINT32_T, MPI_BOR, comm_),
                 "MPI_Allreduce (optional particle fields)");
        int count = int(mine.size());
        const auto ranks = static_cast<std::size_t>(ranks_);
        std::vector<int> counts(ranks, 0), offsets(ranks, 0);
        checkMpi(MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_),
                 "MPI_Gather (particle counts)");
        std::vector<ParticleRecord> all;
        if (rank_ == 0) {
            std::exclusive_scan(counts.begin(), counts.end(), offsets.begin(), 0);
            all.resize(std::size_t(offsets.back() + counts.back()));
        }
        checkMpi(MPI_Gatherv(mine.data(), count, halo_.recordType(), all.data(), counts.data(),
                             offsets.data(), halo_.recordType(), 0, comm_),
                 "MPI_Gatherv (particles)");
        // Particles appended since the last step sit at the end of each
        // rank's part; one process has them at the end of everything.
        auto byKey = [](const ParticleRecord& a, const ParticleRecord& b) { return a.key < b.key; };
        if (!std::is_sorted(all.begin(), all.end(), byKey))
            std::sort(all.begin(), all.end(), byKey);
        ParticleStore result;
        result.keepOptionalFields(optional);
        result.resize(all.size());
        for (std::size_t k = 0; k < all.size(); ++k) setFromRecord(result, k, all[k]);
        result.setNextId(store_.nextId());
        out = std::move(result);
    }

    // Rank r's part of the one-process memory order: the places [offset r,
    // offset r + n r). After a step a rank holds exactly those (its keys);
    // before the first step, or after particles were added or removed, the
    // particles go to the rank whose places hold their keys (the keys are
    // the places [0, total) of one order), sorted there.
    std::uint64_t downloadPart(ParticleStore& out) const override {
        bool inPlace = true;
        for (std::size_t i = 0; i < keys_.size() && inPlace; ++i) inPlace = keys_[i] == offset_ + i;
        int moving = inPlace ? 0 : 1;
        checkMpi(MPI_Allreduce(MPI_IN_PLACE, &moving, 1, MPI_INT, MPI_MAX, comm_),
                 "MPI_Allreduce (particle order)");
        if (!moving) {
            out = store_;
            return offset_;
        }
        unsigned long long first = offset_;
        std::vector<unsigned long long> firsts(static_cast<std::size_t>(ranks_));
        checkMpi(MPI_Allgather(&first, 1, MPI_UNSIGNED_LONG_LONG, firsts.data(), 1,
                               MPI_UNSIGNED_LONG_LONG, comm_),
                 "MPI_Allgather (particle offsets)");
        std::vector<int> sendCounts(static_cast<std::size_t>(ranks_), 0),
            receiveCounts(static_cast<std::size_t>(ranks_)),
            sendOffsets(static_cast<std::size_t>(ranks_), 0),
            receiveOffsets(static_cast<std::size_t>(ranks_), 0);
        std::vector<int> owner(store_.size());
        for (std::size_t i = 0; i < store_.size(); ++i) {
            owner[i] =
                int(std::upper_bound(firsts.begin(), firsts.end(), keys_[i]) - firsts.begin()) - 1;
            ++sendCounts[std::size_t(owner[i])];
        }
        for (int r = 1; r < ranks_; ++r)
            sendOffsets[std::size_t(r)] =
                sendOffsets[std::size_t(r - 1)] + sendCounts[std::size_t(r - 1)];
        std::vector<ParticleRecord> records(store_.size());
        {
            std::vector<int> fill = sendOffsets;
            for (std::size_t i = 0; i < store_.size(); ++i)
                records[std::size_t(fill[std::size_t(owner[i])]++)] = recordOf(store_, i, keys_[i]);
        }
        checkMpi(
            MPI_Alltoall(sendCounts.data(), 1, MPI_INT, receiveCounts.data(), 1, MPI_INT, comm_),
            "MPI_Alltoall (particle order)");
        for (int r = 1; r < ranks_; ++r)
            receiveOffsets[std::size_t(r)] =
                receiveOffsets[std::size_t(r - 1)] + receiveCounts[std::size_t(r - 1)];
        std::vector<ParticleRecord> part(std::size_t(receiveOffsets.back() + receiveCounts.back()));
        checkMpi(MPI_Alltoallv(records.data(), sendCounts.data(), sendOffsets.data(),
                               halo_.recordType(), part.data(), receiveCounts.data(),
                               receiveOffsets.data(), halo_.recordType(), comm_),
                 "MPI_Alltoallv (particle order)");
        std::sort(part.begin(), part.end(),
                  [](const ParticleRecord& a, const ParticleRecord& b) { return a.key < b.key; });
        out = ParticleStore();
        out.keepOptionalFields(store_.keptOptionalFields());
        out.resize(part.size());
        for (std::size_t k = 0; k < part.size(); ++k) setFromRecord(out, k, part[k]);
        out.setNextId(store_.nextId());
        return offset_;
    }

    // Rank 0's state (the other ranks' arguments are ignored) is cut into
    // key ranges: rank 0 gives it all as its part.
    void upload(ParticleStore state) override {
        unsigned long long total = state.size();
        checkMpi(MPI_Bcast(&total, 1, MPI_UNSIGNED_LONG_LONG, 0, comm_), "MPI_Bcast (upload)");
        if (rank_ != 0) state = ParticleStore();
        uploadPart(std::move(state), rank_ == 0 ? 0 : total, total);
    }

    // The parts are cut into key ranges balanced for all particles (a global
    // histogram), and each particle goes to its range's rank; the parts'
    // order is the one-process order (each particle's key: its place there).
    void uploadPart(ParticleStore part, std::uint64_t first, std::uint64_t total) override {
        unsigned long long count = part.size(), nextId = part.nextId();
        checkMpi(MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_),
                 "MPI_Allreduce (upload)");
        if (count != total)
            throw std::logic_error("distributed upload: the parts hold " + std::to_string(count) +
                                   " particles, not " + std::to_string(total));
        // The next id and the optional fields of all (a rank may have no particles).
        checkMpi(MPI_Allreduce(MPI_IN_PLACE, &nextId, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, comm_),
                 "MPI_Allreduce (next id)");
        std::uint32_t optional = part.keptOptionalFields();
        checkMpi(MPI_Allreduce(MPI_IN_PLACE, &optional, 1, MPI_UINT32_T, MPI_BOR, comm_),
                 "MPI_Allreduce (optional particle fields)");
        part.keepOptionalFields(optional);
        keys_.resize(part.size());
        std::iota(keys_.begin(), keys_.end(), first);
        halo_.cutFor(part);
        halo_.migrate(part, keys_);
        halo_.releaseScratch();  // sized for moving every particle
        store_ = std::move(part);
        store_.setNextId(nextId);
        total_ = total;
        nextKey_ = total_;
        updateOffset();
    }

    BackendDiagnostics diagnostics() const override {
        const NeighborSearch& search = solver_.neighborSearch();
        BackendDiagnostics d;
        d.memoryBytes = store_.memoryBytes() + solver_.memoryBytes();
        d.neighborsPerParticle =
            double(search.totalNeighborCount()) / double(std::max<std::size_t>(1, store_.size()));
        d.compactListShare = double(search.compactBlockCount()) /
                             double(std::max<std::size_t>(1, search.blockCount()));
        return d;
    }

    std::vector<RankFigures> rankFigures() const override {
        const unsigned long long mine[4] = {store_.size(), halo_.ghosts(), halo_.peers(),
                                            halo_.bytesSent()};
        std::vector<unsigned long long> all(4 * static_cast<std::size_t>(ranks_));
        checkMpi(MPI_Allgather(mine, 4, MPI_UNSIGNED_LONG_LONG, all.data(), 4,
                               MPI_UNSIGNED_LONG_LONG, comm_),
                 "MPI_Allgather (rank figures)");
        std::vector<RankFigures> figures;
        for (std::size_t r = 0; r < static_cast<std::size_t>(ranks_); ++r)
            figures.push_back({all[4 * r], all[4 * r + 1], all[4 * r + 2], all[4 * r + 3]});
        return figures;
    }

  private:
    // The distributed step: the CPU solver's stages with this process's
    // exchanges between them (backend/mpi/key_range_halo.hpp).
    void insertExchanges(StepPlan<SolverStep>& plan) {
        // After prediction and the swept collision: particles whose x* left
        // this rank's range go to their owners, arrivals and ghosts are added, and
        // the store is put into the order the one-process solver would have
        // them in (so that the stable sort gives the same relative order).
        plan.insertAfter(Stage::CollideSolids, {Stage::Distribute, [this](SolverStep& s) {
                                                    halo_.distribute(s.particles);
                                                    if (s.reactions)
                                                        s.reactions->grow(s.particles.size());
                                                }});
        // After the sort: the owned particles are a contiguous range.
        plan.insertAfter(Stage::NeighborLists, {Stage::OwnedRange, [this](SolverStep& s) {
                                                    halo_.ownedRange(solver_.neighborSearch(),
                                                                     s.ownedBegin, s.ownedEnd);
                                                }});
        // The ghosts' values of what the next pass reads from neighbours.
        plan.insertAfter(Stage::DensityAndLambda, {Stage::ExchangeLambda, [this](SolverStep& s) {
                                                       halo_.exchange(s.withLambda);
                                                       halo_.exchange(s.particles.density.data());
                                                   }});
        plan.insertAfter(
            Stage::CompressionTotals,
            {Stage::SumCompression, [this](SolverStep& s) { halo_.sum(s.compression, 2); },
             whenOn(&StepTerms::errorControlled)});
        plan.insertAfter(Stage::CorrectPositions, {Stage::ExchangePositions, [this](SolverStep& s) {
                                                       halo_.exchange(s.predicted);
                                                   }});
        plan.insertAfter(
            Stage::ViscosityAndVorticity,
            {Stage::ExchangeVorticity, [this](SolverStep& s) { halo_.exchange(*s.vorticity); },
             whenOn(&StepTerms::vorticity)});
        // Surface tension: the ghosts' surface-layer weights s from their
        // owners before the cohesion reads them (a ghost's spread needs
        // neighbours beyond the halo).
        plan.insertAfter(
            Stage::SurfaceLayer,
            {Stage::ExchangeSurfaceLayer, [this](SolverStep& s) { halo_.exchange(s.surfaceLayer); },
             whenOn(&StepTerms::cohesion)});
        // The curvature force: each field of the owned particles, then the
        // ghosts' from their owners before the next pass reads them (a
        // ghost's neighbours beyond the halo are missing: its own would be
        // wrong).
        const auto curvatureOn = whenOn(&StepTerms::curvature);
        plan.insertAfter(Stage::ColourGradient,
                         {Stage::ExchangeColourGradient,
                          [this](SolverStep& s) { halo_.exchange(*s.colourGradient); },
                          curvatureOn});
        plan.insertAfter(Stage::BandNormal,
                         {Stage::ExchangeBandNormal,
                          [this](SolverStep& s) { halo_.exchange(*s.bandNormal); }, curvatureOn});
        plan.insertAfter(Stage::Curvature,
                         {Stage::ExchangeCurvature,
                          [this](SolverStep& s) { halo_.exchange(s.curvature); }, curvatureOn});
        // End of the step: the ghosts are dropped.
        plan.insertAfter(Stage::BoundaryResponse,
                         {Stage::Collect, [this](SolverStep& s) { halo_.collect(s.particles); }});
    }

    // After a step: the owned particles in their sorted order are the
    // one-process order's range [offset, offset + size) of this rank.
    void renumber() {
        updateOffset();
        keys_.resize(store_.size());
        std::iota(keys_.begin(), keys_.end(), offset_);
        nextKey_ = total_;
        unsigned long long mine = store_.size(), total = 0;
        checkMpi(MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_),
                 "MPI_Allreduce (particle count)");
        if (total != total_)
            throw std::logic_error("distributed step: " + std::to_string(total) +
                                   " particles after the step, " + std::to_string(total_) +
                                   " before");
    }
    void updateOffset() {
        unsigned long long mine = store_.size(), before = 0;
        checkMpi(MPI_Exscan(&mine, &before, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm_),
                 "MPI_Exscan (particle offsets)");
        offset_ = rank_ == 0 ? 0 : before;  // MPI_Exscan leaves rank 0's undefined
    }

    MPI_Comm comm_ = MPI_COMM_WORLD;
    int rank_ = 0;
    int ranks_ = 1;
    Solver solver_;
    KeyRangeHalo halo_;
    ParticleStore store_;              // the particles this rank owns
    std::vector<std::uint64_t> keys_;  // their places in the one-process order
    std::uint64_t total_ = 0;          // particles on all ranks
    std::uint64_t nextKey_ = 0;        // the key the next appended particle gets
    std::uint64_t offset_ = 0;         // particles on the ranks before this one
    StageTimes times_;
    ReactionAccumulator reactions_;
    std::vector<SolidReaction> lastReactions_;
};

}  // namespace

std::unique_ptr<Backend> makeMpiBackend(const SimulationParams& params,
                                        const BackendOptions& options) {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized)
        throw std::runtime_error("the mpi backend needs MPI: start pbf with mpirun or srun");
    return std::make_unique<MpiBackend>(params, options);
}

}  // namespace pbf
