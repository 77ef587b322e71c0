// Checkpoints written and read by all ranks of a distributed run at once
// (include/pbf/io/checkpoint.hpp: writeCheckpointFromRanks,
// readCheckpointFromRanks), in the one-process file format
// (checkpoint_format.hpp).
//
// The particle arrays are the payload's bulk; each array is the places
// [0, N) of the memory order, so rank r's part [first, first + n) goes at a
// fixed offset in each array, known from N alone. Rank 0 writes the
// header, the small fields before and after the arrays and each array's
// length. The checksum is a CRC-32: each rank sums its parts of the arrays,
// and rank 0 combines the sums in file order (crc32_combine) with its own
// pieces', which gives the CRC of the whole payload without any rank holding
// it. Reading is the same in reverse: rank 0 reads the small fields, every
// rank its share of each array, and the ranks' sums must combine to the
// header's checksum.
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/binary_stream.hpp"
#include "io/checkpoint_format.hpp"
#include "io/checkpoint_particles.hpp"
#include "pbf/core/distributed.hpp"
#include "pbf/io/checkpoint.hpp"
#include "pbf/io/io.hpp"

#ifdef PBF_HAVE_MPI
#include <mpi.h>

#include "io/ranks_file.hpp"
#endif

namespace pbf {

#ifdef PBF_HAVE_MPI
namespace {

using detail::SavedArray;

// Rank 0 gets every rank's checksums of its parts of the arrays
// (rank-major) and their values per array.
std::vector<unsigned long long> gatherSums(const std::vector<unsigned long long>& mine) {
    std::vector<unsigned long long> all(
        distributed::rank() == 0 ? mine.size() * std::size_t(distributed::size()) : 0);
    MPI_Gather(mine.data(), int(mine.size()), MPI_UNSIGNED_LONG_LONG, all.data(), int(mine.size()),
               MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    return all;
}

// The payload's checksum from its pieces: prefix, then each array's length
// and the ranks' parts of it in rank order (`sums`: per rank, the part's
// CRC then its value count, for each array), then the suffix.
std::uint64_t combinedChecksum(const std::string& prefix, const std::vector<SavedArray>& arrays,
                               const std::vector<std::uint64_t>& lengths,
                               const std::vector<unsigned long long>& sums,
                               const std::string& suffix) {
    const std::size_t perRank = 2 * arrays.size();
    std::uint64_t crc = detail::checksum(prefix.data(), prefix.size());
    for (std::size_t k = 0; k < arrays.size(); ++k) {
        crc = detail::checksum(&lengths[k], sizeof(std::uint64_t), crc);
        for (int r = 0; r < distributed::size(); ++r) {
            const unsigned long long* s = sums.data() + std::size_t(r) * perRank + 2 * k;
            crc = detail::combineChecksums(crc, s[0], s[1] * arrays[k].valueBytes);
        }
    }
    return detail::checksum(suffix.data(), suffix.size(), crc);
}

// What rank 0 reads outside the arrays, for every rank.
struct Layout {
    std::string prefix, suffix;
    std::vector<std::uint64_t> lengths, offsets;  // each array's values and first value's byte
    std::uint64_t checksum = 0;
};

Layout readLayout(const std::filesystem::path& path, const std::vector<SavedArray>& arrays) {
    const std::string name = path.string();
    std::ifstream in(path, std::ios::binary);
    if (!in) detail::fail(name, "cannot open checkpoint");
    const detail::CheckpointHeader header = detail::readCheckpointHeader(in, name);
    const std::uint64_t end = detail::kHeaderBytes + header.payloadBytes;
    auto bytesAt = [&](std::uint64_t at, std::uint64_t n, const char* what) {
        if (at > end || n > end - at)
            detail::fail(name, std::string("corrupt checkpoint: ") + what);
        std::string bytes(std::size_t(n), '\0');
        in.seekg(std::streamoff(at));
        if (!in.read(bytes.data(), std::streamsize(n)))
            detail::fail(name, "cannot read the checkpoint");
        return bytes;
    };
    auto u64At = [&](std::uint64_t at, const char* what) {
        std::uint64_t v = 0;
        std::memcpy(&v, bytesAt(at, 8, what).data(), 8);
        return v;
    };
    Layout layout;
    layout.checksum = header.checksum;
    // Fingerprint (8), version string (length, bytes), frame (4), time (8), next id (8).
    const std::uint64_t versionBytes = u64At(detail::kHeaderBytes + 8, "pbf version");
    if (versionBytes > detail::kMaxStringBytes)
        detail::fail(name, "corrupt checkpoint: pbf version");
    const std::uint64_t prefixBytes = 8 + 8 + versionBytes + 4 + 8 + 8;
    layout.prefix = bytesAt(detail::kHeaderBytes, prefixBytes, "header fields");
    std::uint64_t at = detail::kHeaderBytes + prefixBytes;
    for (const SavedArray& a : arrays) {
        const std::uint64_t n = u64At(at, "particle array length");
        if (n > (end - at - 8) / a.valueBytes)
            detail::fail(name, "corrupt checkpoint: particle array length");
        layout.lengths.push_back(n);
        layout.offsets.push_back(at + 8);
        at += 8 + n * a.valueBytes;
    }
    layout.suffix = bytesAt(at, end - at, "the fields after the particles");
    return layout;
}

}  // namespace
#endif

void writeCheckpointFromRanks(const std::filesystem::path& path, const Checkpoint& c) {
    if (distributed::size() == 1) {
        if (c.total != 0 && (c.first != 0 || c.particles.size() != c.total))
            throw std::logic_error("writeCheckpointFromRanks: one process holds a part");
        writeCheckpoint(path, c);
        return;
    }
#ifdef PBF_HAVE_MPI
    const ParticleStore& p = c.particles;
    const std::uint64_t total = distributed::sumOverRanks(p.size());
    if (distributed::anyRank(c.first != distributed::sumOverRanksBefore(p.size())))
        throw std::logic_error("writeCheckpointFromRanks: the ranks' parts are not in rank order");
    const std::string prefix = detail::checkpointPrefix(c), suffix = detail::checkpointSuffix(c);
    const std::vector<SavedArray> arrays = detail::savedArrays(p);
    std::vector<std::uint64_t> lengths, offsets;
    std::vector<unsigned long long> mine;
    std::uint64_t at = detail::kHeaderBytes + prefix.size();
    for (const SavedArray& a : arrays) {
        lengths.push_back(a.kept ? total : 0);
        offsets.push_back(at + 8);
        at += 8 + lengths.back() * a.valueBytes;
        const std::uint64_t n = a.kept ? p.size() : 0;
        mine.insert(mine.end(), {detail::checksum(a.data, n * a.valueBytes), n});
    }
    const std::uint64_t suffixAt = at;
    const std::vector<unsigned long long> sums = gatherSums(mine);

    detail::RanksFileWriter file(path);
    if (distributed::rank() == 0) {
        const std::string header =
            detail::checkpointHeader(suffixAt + suffix.size() - detail::kHeaderBytes,
                                     combinedChecksum(prefix, arrays, lengths, sums, suffix));
        file.writeAt(0, header.data(), header.size());
        file.writeAt(detail::kHeaderBytes, prefix.data(), prefix.size());
        for (std::size_t k = 0; k < arrays.size(); ++k)
            file.writeAt(offsets[k] - 8, &lengths[k], sizeof(std::uint64_t));
        file.writeAt(suffixAt, suffix.data(), suffix.size());
    }
    for (std::size_t k = 0; k < arrays.size(); ++k) {
        const std::uint64_t bytes = arrays[k].kept ? p.size() * arrays[k].valueBytes : 0;
        file.writeAtAll(offsets[k] + c.first * arrays[k].valueBytes, arrays[k].data, bytes);
    }
    file.commit();
#else
    writeCheckpoint(path, c);
#endif
}

Checkpoint readCheckpointFromRanks(const std::filesystem::path& path) {
    if (distributed::size() == 1) return readCheckpoint(path);
#ifdef PBF_HAVE_MPI
    const std::string name = path.string();
    ParticleStore shape;  // the arrays' value sizes
    shape.keepOptionalFields(~std::uint32_t{0});
    const std::vector<SavedArray> arrays = detail::savedArrays(shape);
    // Rank 0 reads what lies outside the arrays; every rank gets it.
    std::string packed;
    if (distributed::rank() == 0) {
        try {
            const Layout layout = readLayout(path, arrays);
            detail::BinaryWriter w;
            w.value<char>('1');
            w.string(layout.prefix);
            w.string(layout.suffix);
            w.array(layout.lengths);
            w.array(layout.offsets);
            w.value(layout.checksum);
            packed = w.bytes();
        } catch (const std::exception& e) {
            packed = std::string("0") + e.what();
        }
    }
    packed = distributed::broadcast(packed);
    if (packed.empty() || packed[0] != '1')
        throw IoError(packed.empty() ? name + ": cannot read the checkpoint" : packed.substr(1));
    Layout layout;
    {
        detail::BinaryReader r(packed, name);
        r.value<char>("status");
        layout.prefix = r.string("header fields");
        layout.suffix = r.string("fields after the particles");
        r.array(layout.lengths, "array lengths");
        r.array(layout.offsets, "array offsets");
        layout.checksum = r.value<std::uint64_t>("checksum");
    }

    // This rank's share of every array, read into a payload of its own.
    std::uint64_t count = 0;
    for (std::uint64_t n : layout.lengths) count = std::max(count, n);
    const auto rank = std::uint64_t(distributed::rank()),
               ranks = std::uint64_t(distributed::size());
    const std::uint64_t first = count * rank / ranks, last = count * (rank + 1) / ranks;
    std::string payload = layout.prefix;
    std::vector<unsigned long long> mine;
    {
        detail::RanksFileReader file(path);
        for (std::size_t k = 0; k < arrays.size(); ++k) {
            // An array shorter than the others (corrupt) is read as empty
            // here; deserializing the part refuses it.
            const std::uint64_t n = layout.lengths[k] == count ? last - first : 0;
            const std::uint64_t bytes = n * arrays[k].valueBytes;
            payload.append(reinterpret_cast<const char*>(&n), sizeof n);
            const std::size_t at = payload.size();
            payload.resize(at + bytes);
            file.readAtAll(layout.offsets[k] + first * arrays[k].valueBytes, payload.data() + at,
                           bytes, "the particle arrays");
            mine.insert(mine.end(), {detail::checksum(payload.data() + at, bytes), n});
        }
    }
    payload += layout.suffix;
    const std::vector<unsigned long long> sums = gatherSums(mine);
    const bool corrupt =
        distributed::rank() == 0 && combinedChecksum(layout.prefix, arrays, layout.lengths, sums,
                                                     layout.suffix) != layout.checksum;
    if (distributed::anyRank(corrupt))
        detail::fail(name, "checkpoint is corrupt (checksum mismatch)");
    Checkpoint c;
    std::string error;
    try {
        c = detail::deserializeCheckpoint(payload, name);
    } catch (const std::exception& e) {
        error = e.what();
    }
    detail::agreeOnError(error);
    c.first = first;
    c.total = count;
    return c;
#else
    return readCheckpoint(path);
#endif
}

}  // namespace pbf
