#include "backend/mpi/slab_halo.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pbf {

void checkMpi(int code, const char* call) {
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw std::runtime_error(std::string(call) + " failed: " + std::string(text, length));
}

SlabHalo::SlabHalo(MPI_Comm comm, const NeighborSearch& grid) : comm_(comm), grid_(grid) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &ranks_);
    const std::uint32_t planes = grid_.planeCount();
    if (std::uint32_t(ranks_) > planes)
        throw std::runtime_error(
            std::to_string(ranks_) + " ranks need at least as many planes of grid cells (one " +
            "kernel radius thick) along the domain's longest axis; this domain has " +
            std::to_string(planes) + ": run with at most " + std::to_string(planes) + " ranks");
    checkMpi(MPI_Type_contiguous(int(sizeof(ParticleRecord)), MPI_BYTE, &recordType_),
             "MPI_Type_contiguous");
    checkMpi(MPI_Type_commit(&recordType_), "MPI_Type_commit");
    // Equal slabs until the first histogram (upload and every step re-cut).
    cuts_.resize(ranks_ + 1);
    for (int r = 0; r <= ranks_; ++r)
        cuts_[r] = std::uint32_t(std::uint64_t(planes) * std::uint64_t(r) / std::uint64_t(ranks_));
    lo_ = cuts_[rank_];
    hi_ = cuts_[rank_ + 1];
    sendCounts_.resize(ranks_);
    receiveCounts_.resize(ranks_);
    sendOffsets_.resize(ranks_);
    receiveOffsets_.resize(ranks_);
}

SlabHalo::~SlabHalo() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Type_free(&recordType_);
}

int SlabHalo::ownerOf(const Vec3& x) const {
    const std::uint32_t plane = grid_.planeOf(x);
    // The last cut at or below the plane.
    return int(std::upper_bound(cuts_.begin() + 1, cuts_.end() - 1, plane) - cuts_.begin()) - 1;
}

// Greedy prefix cuts: cut k at the plane whose prefix count is nearest to
// k / N of all particles, keeping at least one plane per rank (a rank's
// ghosts must come from its neighbours only).
std::vector<std::uint32_t> SlabHalo::cutsFor(const std::vector<std::uint64_t>& counts) const {
    const std::uint32_t planes = std::uint32_t(counts.size());
    std::vector<std::uint64_t> prefix(planes + 1, 0);
    for (std::uint32_t c = 0; c < planes; ++c) prefix[c + 1] = prefix[c] + counts[c];
    const double total = double(prefix[planes]);
    std::vector<std::uint32_t> cuts(ranks_ + 1, 0);
    cuts[ranks_] = planes;
    for (int k = 1; k < ranks_; ++k) {
        const double target = total * k / ranks_;
        const std::uint32_t first = cuts[k - 1] + 1;
        const std::uint32_t last = planes - std::uint32_t(ranks_ - k);
        std::uint32_t best = first;
        for (std::uint32_t c = first; c <= last; ++c)
            if (std::abs(double(prefix[c]) - target) < std::abs(double(prefix[best]) - target))
                best = c;
        cuts[k] = best;
    }
    return cuts;
}

void SlabHalo::balance(const std::vector<std::uint64_t>& counts, bool force) {
    auto busiest = [&](const std::vector<std::uint32_t>& cuts) {
        std::uint64_t most = 0;
        for (int r = 0; r < ranks_; ++r) {
            std::uint64_t load = 0;
            for (std::uint32_t c = cuts[r]; c < cuts[r + 1]; ++c) load += counts[c];
            most = std::max(most, load);
        }
        return most;
    };
    std::vector<std::uint32_t> cuts = cutsFor(counts);
    if (cuts != cuts_ && (force || double(busiest(cuts_)) > 1.05 * double(busiest(cuts)))) {
        cuts_ = std::move(cuts);
        ++rebalances_;
    }
    lo_ = cuts_[rank_];
    hi_ = cuts_[rank_ + 1];
}

// Merges the sorted run [runBegin, end) of entries_ into the sorted entries before it.
void SlabHalo::mergeRun(std::size_t runBegin) {
    auto byKey = [](const Entry& a, const Entry& b) { return a.key < b.key; };
    std::inplace_merge(entries_.begin(), entries_.begin() + std::ptrdiff_t(runBegin),
                       entries_.end(), byKey);
}

void SlabHalo::distribute(ParticleStore& p) {
    const std::size_t n0 = p.size();
    if (!keys_ || keys_->size() != n0)
        throw std::logic_error("SlabHalo::distribute: keys do not match the particles");
    const std::vector<std::uint64_t>& keys = *keys_;

    // Load balance on where the particles are now.
    planes_.resize(n0);
    histogram_.assign(grid_.planeCount(), 0);
    for (std::size_t i = 0; i < n0; ++i) {
        planes_[i] = grid_.planeOf(p.predicted.get(i));
        ++histogram_[planes_[i]];
    }
    checkMpi(MPI_Allreduce(MPI_IN_PLACE, histogram_.data(), int(histogram_.size()), MPI_UINT64_T,
                           MPI_SUM, comm_),
             "MPI_Allreduce (particles per plane)");
    balance(histogram_, false);

    // Migration: particles of other ranks' planes go to them, in store order
    // (key order) per destination.
    auto owner = [&](std::uint32_t plane) {
        return int(std::upper_bound(cuts_.begin() + 1, cuts_.end() - 1, plane) - cuts_.begin()) - 1;
    };
    std::fill(sendCounts_.begin(), sendCounts_.end(), 0);
    entries_.clear();
    for (std::size_t i = 0; i < n0; ++i) {
        const int r = owner(planes_[i]);
        if (r == rank_)
            entries_.push_back({keys[i], std::uint32_t(i)});
        else
            ++sendCounts_[r];
    }
    for (int r = 0, at = 0; r < ranks_; at += sendCounts_[r++]) sendOffsets_[r] = at;
    outgoing_.resize(n0 - entries_.size());
    {
        std::vector<int> fill = sendOffsets_;
        for (std::size_t i = 0; i < n0; ++i) {
            const int r = owner(planes_[i]);
            if (r != rank_) outgoing_[fill[r]++] = recordOf(p, i, keys[i]);
        }
    }
    checkMpi(MPI_Alltoall(sendCounts_.data(), 1, MPI_INT, receiveCounts_.data(), 1, MPI_INT, comm_),
             "MPI_Alltoall (migrating particles)");
    int arriving = 0;
    for (int r = 0; r < ranks_; ++r) {
        receiveOffsets_[r] = arriving;
        arriving += receiveCounts_[r];
    }
    incoming_.resize(std::size_t(arriving));
    checkMpi(MPI_Alltoallv(outgoing_.data(), sendCounts_.data(), sendOffsets_.data(), recordType_,
                           incoming_.data(), receiveCounts_.data(), receiveOffsets_.data(),
                           recordType_, comm_),
             "MPI_Alltoallv (migrating particles)");
    // The store is in key order and so is each sender's part: merge the runs.
    for (int r = 0; r < ranks_; ++r) {
        const std::size_t runBegin = entries_.size();
        for (int k = 0; k < receiveCounts_[r]; ++k)
            entries_.push_back({incoming_[receiveOffsets_[r] + k].key,
                                std::uint32_t(n0 + receiveOffsets_[r] + k)});
        if (runBegin > 0 && entries_.size() > runBegin) mergeRun(runBegin);
    }
    auto recordAt = [&](const Entry& e) {
        return e.source < n0 ? recordOf(p, e.source, e.key) : incoming_[e.source - n0];
    };

    // Ghosts: this rank's first plane for rank - 1, its last for rank + 1
    // (owned particles in key order; the ghosts' neighbours are not needed).
    ghostsDown_.clear();
    ghostsUp_.clear();
    for (const Entry& e : entries_) {
        const std::uint32_t plane = e.source < n0
                                        ? planes_[e.source]
                                        : grid_.planeOf(predictedOf(incoming_[e.source - n0]));
        if (plane == lo_ && rank_ > 0) ghostsDown_.push_back(recordAt(e));
        if (plane + 1 == hi_ && rank_ + 1 < ranks_) ghostsUp_.push_back(recordAt(e));
    }
    const int below = rank_ > 0 ? rank_ - 1 : MPI_PROC_NULL;
    const int above = rank_ + 1 < ranks_ ? rank_ + 1 : MPI_PROC_NULL;
    int sendDown = int(ghostsDown_.size()), sendUp = int(ghostsUp_.size());
    int fromAbove = 0, fromBelow = 0;
    checkMpi(MPI_Sendrecv(&sendDown, 1, MPI_INT, below, 1, &fromAbove, 1, MPI_INT, above, 1, comm_,
                          MPI_STATUS_IGNORE),
             "MPI_Sendrecv (ghost counts)");
    checkMpi(MPI_Sendrecv(&sendUp, 1, MPI_INT, above, 2, &fromBelow, 1, MPI_INT, below, 2, comm_,
                          MPI_STATUS_IGNORE),
             "MPI_Sendrecv (ghost counts)");
    const std::size_t arrived = incoming_.size();
    incoming_.resize(arrived + std::size_t(fromBelow) + std::size_t(fromAbove));
    ParticleRecord* belowRecords = incoming_.data() + arrived;
    ParticleRecord* aboveRecords = belowRecords + fromBelow;
    checkMpi(MPI_Sendrecv(ghostsDown_.data(), sendDown, recordType_, below, 3, aboveRecords,
                          fromAbove, recordType_, above, 3, comm_, MPI_STATUS_IGNORE),
             "MPI_Sendrecv (ghosts)");
    checkMpi(MPI_Sendrecv(ghostsUp_.data(), sendUp, recordType_, above, 4, belowRecords, fromBelow,
                          recordType_, below, 4, comm_, MPI_STATUS_IGNORE),
             "MPI_Sendrecv (ghosts)");
    ghostsBelow_ = std::size_t(fromBelow);
    ghostsAbove_ = std::size_t(fromAbove);
    // Ghosts from below have smaller keys than everything owned here, those
    // from above larger ones (ranks hold consecutive ranges of the order),
    // except particles emitted since the last step: merge, do not assume.
    for (std::size_t k = arrived; k < incoming_.size();) {
        const std::size_t runEnd =
            k < arrived + ghostsBelow_ ? arrived + ghostsBelow_ : incoming_.size();
        const std::size_t runBegin = entries_.size();
        for (; k < runEnd; ++k) entries_.push_back({incoming_[k].key, std::uint32_t(n0 + k)});
        if (runBegin > 0 && entries_.size() > runBegin) mergeRun(runBegin);
    }

    // The new store, in key order.
    const std::size_t n = entries_.size();
    next_.keepOptionalFields(p.keptOptionalFields());
    next_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Entry& e = entries_[k];
        if (e.source < n0)
            next_.copyParticle(k, p, e.source);
        else
            setFromRecord(next_, k, incoming_[e.source - n0]);
    }
    next_.setNextId(p.nextId());
    std::swap(p, next_);
    size_ = n;
}

void SlabHalo::ownedRange(const NeighborSearch& search, std::size_t& begin, std::size_t& end) {
    const std::size_t perPlane = search.cellsPerPlane();
    begin_ = search.cellStart(lo_ * perPlane);
    end_ = search.cellStart(hi_ * perPlane);
    downEnd_ = search.cellStart((lo_ + 1) * perPlane);
    upBegin_ = search.cellStart((hi_ - 1) * perPlane);
    if (begin_ != ghostsBelow_ || size_ - end_ != ghostsAbove_)
        throw std::logic_error("SlabHalo: ghosts outside the planes next to the slab (" +
                               std::to_string(ghostsBelow_) + " below, " + std::to_string(begin_) +
                               " sorted before the slab)");
    begin = begin_;
    end = end_;
}

template <class T>
void SlabHalo::exchangeBytes(T* data, std::size_t bytes) {
    const int below = rank_ > 0 ? rank_ - 1 : MPI_PROC_NULL;
    const int above = rank_ + 1 < ranks_ ? rank_ + 1 : MPI_PROC_NULL;
    const int sendDown = rank_ > 0 ? int((downEnd_ - begin_) * bytes) : 0;
    const int sendUp = rank_ + 1 < ranks_ ? int((end_ - upBegin_) * bytes) : 0;
    checkMpi(
        MPI_Sendrecv(data + begin_, sendDown, MPI_BYTE, below, 5, data + end_,
                     int((size_ - end_) * bytes), MPI_BYTE, above, 5, comm_, MPI_STATUS_IGNORE),
        "MPI_Sendrecv (halo)");
    checkMpi(MPI_Sendrecv(data + upBegin_, sendUp, MPI_BYTE, above, 6, data, int(begin_ * bytes),
                          MPI_BYTE, below, 6, comm_, MPI_STATUS_IGNORE),
             "MPI_Sendrecv (halo)");
}

void SlabHalo::sum(std::int64_t* values, int count) {
    checkMpi(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_INT64_T, MPI_SUM, comm_),
             "MPI_Allreduce (iteration control)");
}

void SlabHalo::exchange(PackedPoint* records) {
    exchangeBytes(records, sizeof(PackedPoint));
}

void SlabHalo::exchange(float* values) {
    exchangeBytes(values, sizeof(float));
}

void SlabHalo::exchange(Float3Array& values) {
    exchangeBytes(values.x.data(), sizeof(float));
    exchangeBytes(values.y.data(), sizeof(float));
    exchangeBytes(values.z.data(), sizeof(float));
}

void SlabHalo::collect(ParticleStore& p) {
    p.keepRange(begin_, end_);
}

}  // namespace pbf
