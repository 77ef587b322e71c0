#include "backend/mpi/key_range_halo.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/cell_key.hpp"

namespace pbf {
namespace {

constexpr int kBlockShift = cell_key::kRowBits;  // balance by the key's 64-cell rows (key >> 6)

}  // namespace

void checkMpi(int code, const char* call) {
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw std::runtime_error(std::string(call) + " failed: " + std::string(text, length));
}

KeyRangeHalo::KeyRangeHalo(MPI_Comm comm, const NeighborSearch& search)
    : comm_(comm), search_(search) {
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &ranks_);
    checkMpi(MPI_Type_contiguous(int(sizeof(ParticleRecord)), MPI_BYTE, &recordType_),
             "MPI_Type_contiguous");
    checkMpi(MPI_Type_commit(&recordType_), "MPI_Type_commit");
    // Equal shares of the domain's keys until the first cut by particles
    // (upload, and distribute when the counts differ).
    const std::uint64_t keys = std::uint64_t{1}
                               << cell_key::keyBits(search_.frame().maxCoordinate + 1);
    std::vector<std::uint64_t> cuts(std::size_t(ranks_) + 1);
    for (int r = 0; r <= ranks_; ++r) cuts[std::size_t(r)] = keys / std::uint64_t(ranks_) * r;
    cuts.back() = keys;
    adoptCuts(std::move(cuts));
    const auto ranks = std::size_t(ranks_);
    for (auto* v : {&sendCounts_, &receiveCounts_, &sendOffsets_, &receiveOffsets_, &sendBytes_,
                    &receiveBytes_, &sendByteOffsets_, &receiveByteOffsets_})
        v->resize(ranks);
    sendIndex_.resize(ranks);
    receiveIndex_.resize(ranks);
}

KeyRangeHalo::~KeyRangeHalo() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Type_free(&recordType_);
}

void KeyRangeHalo::adoptCuts(std::vector<std::uint64_t> cuts) {
    cuts_ = std::move(cuts);
    lo_ = cuts_[std::size_t(rank_)];
    hi_ = cuts_[std::size_t(rank_) + 1];
    peersKey_ = ~std::uint64_t{0};
}

int KeyRangeHalo::ownerOfKey(std::uint64_t cellKey) const {
    // The last cut at or below the key (ranks with empty ranges skipped).
    return int(std::upper_bound(cuts_.begin() + 1, cuts_.end() - 1, cellKey) - cuts_.begin()) - 1;
}

int KeyRangeHalo::ownerOf(const Vec3& x) const {
    return ownerOfKey(search_.keyOf(x));
}

const std::vector<int>& KeyRangeHalo::peersOf(std::uint64_t cellKey) {
    if (cellKey == peersKey_) return peers_;
    peersKey_ = cellKey;
    peers_.clear();
    const cell_key::CellCoords c = cell_key::cellCoords(cellKey);
    const std::uint32_t top = search_.frame().maxCoordinate;
    const auto down = [](std::uint32_t v) { return v > 0 ? v - 1 : v; };
    const auto up = [top](std::uint32_t v) { return v < top ? v + 1 : v; };
    // The key grows with each coordinate, so the neighbourhood's keys lie
    // between its corners': most cells are inside this rank's range.
    if (cell_key::cellKey({down(c.x), down(c.y), down(c.z)}) >= lo_ &&
        cell_key::cellKey({up(c.x), up(c.y), up(c.z)}) < hi_)
        return peers_;
    for (std::uint32_t z = down(c.z); z <= up(c.z); ++z)
        for (std::uint32_t y = down(c.y); y <= up(c.y); ++y)
            for (std::uint32_t x = down(c.x); x <= up(c.x); ++x) {
                const int r = ownerOfKey(cell_key::cellKey({x, y, z}));
                if (r == rank_) continue;
                const auto at = std::lower_bound(peers_.begin(), peers_.end(), r);
                if (at == peers_.end() || *at != r) peers_.insert(at, r);
            }
    return peers_;
}

// Greedy prefix cuts at block boundaries: cut k where the count of the
// blocks before it is nearest to k / N of all particles.
std::vector<std::uint64_t> KeyRangeHalo::cutsFor(const std::vector<std::uint64_t>& blocks,
                                                 const std::vector<std::uint64_t>& counts) const {
    const std::size_t b = blocks.size();
    std::vector<std::uint64_t> prefix(b + 1, 0);
    for (std::size_t k = 0; k < b; ++k) prefix[k + 1] = prefix[k] + counts[k];
    const double total = double(prefix[b]);
    std::vector<std::uint64_t> cuts(std::size_t(ranks_) + 1, 0);
    cuts.back() = cuts_.back();
    std::size_t at = 0;
    for (int k = 1; k < ranks_; ++k) {
        const double target = total * k / ranks_;
        while (at < b && std::abs(double(prefix[at + 1]) - target) <=
                             std::abs(double(prefix[at]) - target))
            ++at;
        cuts[std::size_t(k)] = at < b ? blocks[at] << kBlockShift : cuts.back();
    }
    return cuts;
}

void KeyRangeHalo::globalHistogram(const std::vector<std::uint64_t>& cellKeys,
                                   std::vector<std::uint64_t>& keys,
                                   std::vector<std::uint64_t>& counts) const {
    // This rank's (block, count) pairs, gathered sparse from all ranks.
    std::vector<std::uint64_t> blocks(cellKeys.size());
    for (std::size_t i = 0; i < cellKeys.size(); ++i) blocks[i] = cellKeys[i] >> kBlockShift;
    std::sort(blocks.begin(), blocks.end());
    std::vector<std::uint64_t> pairs;
    for (std::size_t i = 0; i < blocks.size();) {
        std::size_t j = i;
        while (j < blocks.size() && blocks[j] == blocks[i]) ++j;
        pairs.insert(pairs.end(), {blocks[i], std::uint64_t(j - i)});
        i = j;
    }
    int size = int(pairs.size());
    std::vector<int> sizes(static_cast<std::size_t>(ranks_)), offsets(static_cast<std::size_t>(ranks_));
    checkMpi(MPI_Allgather(&size, 1, MPI_INT, sizes.data(), 1, MPI_INT, comm_),
             "MPI_Allgather (histogram sizes)");
    int all = 0;
    for (int r = 0; r < ranks_; ++r) {
        offsets[std::size_t(r)] = all;
        all += sizes[std::size_t(r)];
    }
    std::vector<std::uint64_t> gathered(static_cast<std::size_t>(all));
    checkMpi(MPI_Allgatherv(pairs.data(), size, MPI_UINT64_T, gathered.data(), sizes.data(),
                            offsets.data(), MPI_UINT64_T, comm_),
             "MPI_Allgatherv (histogram)");
    std::vector<std::pair<std::uint64_t, std::uint64_t>> merged;
    for (std::size_t k = 0; k + 1 < gathered.size(); k += 2)
        merged.emplace_back(gathered[k], gathered[k + 1]);
    std::sort(merged.begin(), merged.end());
    keys.clear();
    counts.clear();
    for (const auto& [block, count] : merged) {
        if (!keys.empty() && keys.back() == block) {
            counts.back() += count;
        } else {
            keys.push_back(block);
            counts.push_back(count);
        }
    }
}

void KeyRangeHalo::rebalance(const std::vector<std::uint64_t>& cellKeys) {
    // Cheap test first: the ranks' counts of the particles they hold now.
    unsigned long long mine = cellKeys.size();
    std::vector<unsigned long long> loads(static_cast<std::size_t>(ranks_));
    checkMpi(MPI_Allgather(&mine, 1, MPI_UNSIGNED_LONG_LONG, loads.data(), 1,
                           MPI_UNSIGNED_LONG_LONG, comm_),
             "MPI_Allgather (particles per rank)");
    unsigned long long total = 0, busiest = 0;
    for (unsigned long long l : loads) {
        total += l;
        busiest = std::max(busiest, l);
    }
    if (total == 0) return;
    const double mean = double(total) / ranks_;
    if (double(busiest) <= std::max(1.05, 1.05 * balancedRatio_) * mean) return;

    std::vector<std::uint64_t> keys, counts;
    globalHistogram(cellKeys, keys, counts);
    auto busiestUnder = [&](const std::vector<std::uint64_t>& cuts) {
        std::vector<std::uint64_t> load(std::size_t(ranks_), 0);
        for (std::size_t k = 0; k < keys.size(); ++k) {
            const std::uint64_t first = keys[k] << kBlockShift;
            const int r =
                int(std::upper_bound(cuts.begin() + 1, cuts.end() - 1, first) - cuts.begin()) - 1;
            load[std::size_t(r)] += counts[k];
        }
        return double(*std::max_element(load.begin(), load.end()));
    };
    std::vector<std::uint64_t> cuts = cutsFor(keys, counts);
    const double before = busiestUnder(cuts_), after = busiestUnder(cuts);
    if (cuts != cuts_ && 1.05 * after < before) {
        adoptCuts(std::move(cuts));
        ++rebalances_;
        balancedRatio_ = after / mean;
    } else {
        balancedRatio_ = before / mean;  // the blocks allow no better: do not retry every step
    }
}

void KeyRangeHalo::cutFor(const ParticleStore& particles) {
    std::vector<std::uint64_t> cellKeys(particles.size());
    for (std::size_t i = 0; i < cellKeys.size(); ++i)
        cellKeys[i] = search_.keyOf(particles.predicted.get(i));
    std::vector<std::uint64_t> keys, counts;
    globalHistogram(cellKeys, keys, counts);
    std::vector<std::uint64_t> cuts = cutsFor(keys, counts);
    if (cuts != cuts_) ++rebalances_;
    adoptCuts(std::move(cuts));
    balancedRatio_ = 1.0;
}

// Merges the sorted run [runBegin, end) of entries_ into the sorted entries before it.
void KeyRangeHalo::mergeRun(std::size_t runBegin) {
    auto byKey = [](const Entry& a, const Entry& b) { return a.key < b.key; };
    std::inplace_merge(entries_.begin(), entries_.begin() + std::ptrdiff_t(runBegin),
                       entries_.end(), byKey);
}

void KeyRangeHalo::migrateEntries(const ParticleStore& p, const std::vector<std::uint64_t>& keys) {
    // Particles of other ranks' cells go to them, in store order (key order)
    // per destination.
    const std::size_t n0 = p.size();
    std::fill(sendCounts_.begin(), sendCounts_.end(), 0);
    entries_.clear();
    for (std::size_t i = 0; i < n0; ++i) {
        const int r = ownerOfKey(cellKeys_[i]);
        if (r == rank_)
            entries_.push_back({keys[i], std::uint32_t(i)});
        else
            ++sendCounts_[std::size_t(r)];
    }
    for (int r = 0, at = 0; r < ranks_; at += sendCounts_[std::size_t(r++)])
        sendOffsets_[std::size_t(r)] = at;
    outgoing_.resize(n0 - entries_.size());
    std::vector<int> fill = sendOffsets_;
    for (std::size_t i = 0; i < n0; ++i) {
        const int r = ownerOfKey(cellKeys_[i]);
        if (r != rank_) outgoing_[std::size_t(fill[std::size_t(r)]++)] = recordOf(p, i, keys[i]);
    }
    incoming_.clear();
    exchangeRecords(n0, "MPI_Alltoallv (migrating particles)");
}

// Sends outgoing_ (sendCounts_ records to each rank, at sendOffsets_) and
// appends what arrives to incoming_ and its entries to entries_, merged in
// key order (the store is in key order and so is each sender's part).
std::size_t KeyRangeHalo::exchangeRecords(std::size_t storeSize, const char* what) {
    checkMpi(MPI_Alltoall(sendCounts_.data(), 1, MPI_INT, receiveCounts_.data(), 1, MPI_INT, comm_),
             what);
    int arriving = 0;
    for (int r = 0; r < ranks_; ++r) {
        receiveOffsets_[std::size_t(r)] = arriving;
        arriving += receiveCounts_[std::size_t(r)];
    }
    const std::size_t before = incoming_.size();
    incoming_.resize(before + std::size_t(arriving));
    for (int r = 0; r < ranks_; ++r)
        bytesSent_ += std::uint64_t(sendCounts_[std::size_t(r)]) * sizeof(ParticleRecord);
    checkMpi(MPI_Alltoallv(outgoing_.data(), sendCounts_.data(), sendOffsets_.data(), recordType_,
                           incoming_.data() + before, receiveCounts_.data(), receiveOffsets_.data(),
                           recordType_, comm_),
             what);
    for (int r = 0; r < ranks_; ++r) {
        const std::size_t runBegin = entries_.size();
        for (int k = 0; k < receiveCounts_[std::size_t(r)]; ++k) {
            const std::size_t at = before + std::size_t(receiveOffsets_[std::size_t(r)] + k);
            entries_.push_back({incoming_[at].key, std::uint32_t(storeSize + at)});
        }
        if (runBegin > 0 && entries_.size() > runBegin) mergeRun(runBegin);
    }
    return std::size_t(arriving);
}

// The store rebuilt from entries_, in key order, in place (no second copy
// of the store): the staying particles (in store order among the entries)
// move to the front, then the entries are placed from the back, where an
// entry's place is never before its staying particle's.
void KeyRangeHalo::rebuild(ParticleStore& p) {
    const std::size_t n0 = p.size(), n = entries_.size();
    std::size_t stays = 0;
    for (const Entry& e : entries_)
        if (e.source < n0) {
            if (stays != e.source) p.copyParticle(stays, p, e.source);
            ++stays;
        }
    p.resize(n);
    for (std::size_t k = n, j = stays; k-- > 0;) {
        const Entry& e = entries_[k];
        if (e.source < n0) {
            if (--j != k) p.copyParticle(k, p, j);
        } else {
            setFromRecord(p, k, incoming_[e.source - n0]);
        }
    }
}

void KeyRangeHalo::migrate(ParticleStore& p, std::vector<std::uint64_t>& keys) {
    if (keys.size() != p.size())
        throw std::logic_error("KeyRangeHalo::migrate: keys do not match the particles");
    cellKeys_.resize(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) cellKeys_[i] = search_.keyOf(p.predicted.get(i));
    migrateEntries(p, keys);
    rebuild(p);
    keys.resize(entries_.size());
    for (std::size_t k = 0; k < entries_.size(); ++k) keys[k] = entries_[k].key;
}

void KeyRangeHalo::releaseScratch() {
    std::vector<std::uint64_t>().swap(cellKeys_);
    std::vector<Entry>().swap(entries_);
    std::vector<ParticleRecord>().swap(outgoing_);
    std::vector<ParticleRecord>().swap(incoming_);
}

void KeyRangeHalo::distribute(ParticleStore& p) {
    const std::size_t n0 = p.size();
    if (!keys_ || keys_->size() != n0)
        throw std::logic_error("KeyRangeHalo::distribute: keys do not match the particles");
    cellKeys_.resize(n0);
    for (std::size_t i = 0; i < n0; ++i) cellKeys_[i] = search_.keyOf(p.predicted.get(i));
    rebalance(cellKeys_);
    bytesSent_ = 0;
    migrateEntries(p, *keys_);

    // Ghosts: each owned particle whose cell has a neighbour cell another
    // rank owns goes to that rank (in key order per destination): the
    // (entry, rank) pairs first, then the records grouped by rank.
    ghostPairs_.clear();
    std::fill(sendCounts_.begin(), sendCounts_.end(), 0);
    for (std::size_t k = 0; k < entries_.size(); ++k) {
        const Entry& e = entries_[k];
        const std::uint64_t cellKey = e.source < n0
                                          ? cellKeys_[e.source]
                                          : search_.keyOf(predictedOf(incoming_[e.source - n0]));
        for (int r : peersOf(cellKey)) {
            ghostPairs_.push_back({std::uint32_t(k), r});
            ++sendCounts_[std::size_t(r)];
        }
    }
    for (int r = 0, at = 0; r < ranks_; at += sendCounts_[std::size_t(r++)])
        sendOffsets_[std::size_t(r)] = at;
    outgoing_.resize(ghostPairs_.size());
    {
        std::vector<int> fill = sendOffsets_;
        for (const auto& [k, r] : ghostPairs_) {
            const Entry& e = entries_[k];
            outgoing_[std::size_t(fill[std::size_t(r)]++)] =
                e.source < n0 ? recordOf(p, e.source, e.key) : incoming_[e.source - n0];
        }
    }
    ghostsReceived_ = exchangeRecords(n0, "MPI_Alltoallv (ghosts)");
    rebuild(p);
}

void KeyRangeHalo::ownedRange(const NeighborSearch& search, std::size_t& begin, std::size_t& end) {
    const std::vector<std::uint64_t>& keys = search.sortedKeys();
    begin_ = std::size_t(std::lower_bound(keys.begin(), keys.end(), lo_) - keys.begin());
    end_ = std::size_t(std::lower_bound(keys.begin(), keys.end(), hi_) - keys.begin());
    if (keys.size() - (end_ - begin_) != ghostsReceived_)
        throw std::logic_error("KeyRangeHalo: " + std::to_string(ghostsReceived_) +
                               " ghosts received, " +
                               std::to_string(keys.size() - (end_ - begin_)) +
                               " particles sorted outside this rank's keys");
    // Who gets which values after each pass: both sides list the particles
    // in their sorted order, the one-process order, so the lists match.
    for (int r = 0; r < ranks_; ++r) {
        sendIndex_[std::size_t(r)].clear();
        receiveIndex_[std::size_t(r)].clear();
    }
    for (std::size_t i = begin_; i < end_; ++i)
        for (int r : peersOf(keys[i])) sendIndex_[std::size_t(r)].push_back(std::uint32_t(i));
    for (std::size_t i = 0; i < keys.size(); ++i)
        if (i < begin_ || i >= end_)
            receiveIndex_[std::size_t(ownerOfKey(keys[i]))].push_back(std::uint32_t(i));
    begin = begin_;
    end = end_;
}

template <class T>
void KeyRangeHalo::exchangeBytes(T* data, std::size_t bytes) {
    auto* base = reinterpret_cast<std::byte*>(data);
    int sent = 0, received = 0;
    for (int r = 0; r < ranks_; ++r) {
        const auto k = std::size_t(r);
        sendByteOffsets_[k] = sent;
        receiveByteOffsets_[k] = received;
        sendBytes_[k] = int(sendIndex_[k].size() * bytes);
        receiveBytes_[k] = int(receiveIndex_[k].size() * bytes);
        sent += sendBytes_[k];
        received += receiveBytes_[k];
    }
    sendBuffer_.resize(std::size_t(sent));
    bytesSent_ += std::uint64_t(sent);
    receiveBuffer_.resize(std::size_t(received));
    std::byte* out = sendBuffer_.data();
    for (const auto& list : sendIndex_)
        for (std::uint32_t i : list) {
            std::memcpy(out, base + std::size_t(i) * bytes, bytes);
            out += bytes;
        }
    checkMpi(MPI_Alltoallv(sendBuffer_.data(), sendBytes_.data(), sendByteOffsets_.data(),
                           MPI_BYTE, receiveBuffer_.data(), receiveBytes_.data(),
                           receiveByteOffsets_.data(), MPI_BYTE, comm_),
             "MPI_Alltoallv (halo)");
    const std::byte* in = receiveBuffer_.data();
    for (const auto& list : receiveIndex_)
        for (std::uint32_t i : list) {
            std::memcpy(base + std::size_t(i) * bytes, in, bytes);
            in += bytes;
        }
}

void KeyRangeHalo::sum(std::int64_t* values, int count) {
    checkMpi(MPI_Allreduce(MPI_IN_PLACE, values, count, MPI_INT64_T, MPI_SUM, comm_),
             "MPI_Allreduce (iteration control)");
}

void KeyRangeHalo::exchange(PackedPoint* records) {
    exchangeBytes(records, sizeof(PackedPoint));
}

void KeyRangeHalo::exchange(float* values) {
    exchangeBytes(values, sizeof(float));
}

void KeyRangeHalo::exchange(Float3Array& values) {
    exchangeBytes(values.x.data(), sizeof(float));
    exchangeBytes(values.y.data(), sizeof(float));
    exchangeBytes(values.z.data(), sizeof(float));
}

std::uint64_t KeyRangeHalo::peers() const {
    std::uint64_t n = 0;
    for (int r = 0; r < ranks_; ++r)
        if (!sendIndex_[std::size_t(r)].empty() || !receiveIndex_[std::size_t(r)].empty()) ++n;
    return n;
}

void KeyRangeHalo::collect(ParticleStore& p) {
    p.keepRange(begin_, end_);
}

}  // namespace pbf
