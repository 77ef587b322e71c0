// The particle PLY frame written by all ranks at once (include/pbf/io/io.hpp,
// writeParticlesPlyFromRanks).
//
// The file lists the particles by id; ids have gaps (outlets remove
// particles), so no rank knows where a particle goes from its id alone.
// The ranks split the ids [0, next id) into equal ranges, send each
// particle's vertex to the rank of its range (one Alltoallv), sort what
// they get, and learn their first vertex's place from the counts of the
// ranks before them (MPI_Exscan). Rank 0 writes the header (its length
// follows from the total count); every rank writes its run in one
// collective write. The file is written under a temporary name and renamed
// when whole.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "io/particle_ply.hpp"
#include "pbf/core/distributed.hpp"
#include "pbf/io/io.hpp"

#ifdef PBF_HAVE_MPI
#include <mpi.h>
#endif

namespace pbf {

#ifdef PBF_HAVE_MPI
namespace {

using detail::ParticlePlyRecord;

// The MPI error's text.
std::string mpiError(int code) {
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    return std::string(text, std::size_t(length));
}

// Throws IoError on every rank when the call failed on any (collective:
// every rank must get here), naming the file and the first failing rank's reason.
void agree(int code, const std::filesystem::path& path, const char* what, MPI_Comm comm) {
    int rank = 0, failed = code == MPI_SUCCESS ? -1 : 0;
    MPI_Comm_rank(comm, &rank);
    if (failed == 0) failed = rank;
    int first = -1;
    {
        int mine = failed < 0 ? 1 << 30 : failed, lowest = 0;
        MPI_Allreduce(&mine, &lowest, 1, MPI_INT, MPI_MIN, comm);
        first = lowest == 1 << 30 ? -1 : lowest;
    }
    if (first < 0) return;
    std::string reason = first == rank ? mpiError(code) : std::string();
    int length = int(reason.size());
    MPI_Bcast(&length, 1, MPI_INT, first, comm);
    reason.resize(std::size_t(length));
    MPI_Bcast(reason.data(), length, MPI_CHAR, first, comm);
    throw IoError(path.string() + ": " + what + " failed on rank " + std::to_string(first) + " (" +
                  reason + "); every rank must see the output directory");
}

}  // namespace
#endif

void writeParticlesPlyFromRanks(const std::filesystem::path& path, const ParticleStore& own) {
    if (distributed::size() == 1) {
        writeParticlesPly(path, own);
        return;
    }
#ifdef PBF_HAVE_MPI
    MPI_Comm comm = MPI_COMM_WORLD;
    const int rank = distributed::rank(), ranks = distributed::size();
    // Every id must fit the file's 32 bits: all ranks refuse together.
    unsigned long long ids = own.nextId();
    for (std::uint64_t id : own.id) ids = std::max<unsigned long long>(ids, id + 1);
    MPI_Allreduce(MPI_IN_PLACE, &ids, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, comm);
    plyId(std::max<unsigned long long>(ids, 1) - 1, path);

    // Each vertex to the rank of its id range.
    const std::uint64_t range =
        std::max<std::uint64_t>(1, (ids + std::uint64_t(ranks) - 1) / ranks);
    const auto owner = [range](std::uint32_t id) { return int(id / range); };
    std::vector<int> sendCounts(std::size_t(ranks), 0), receiveCounts(std::size_t(ranks), 0),
        sendOffsets(std::size_t(ranks), 0), receiveOffsets(std::size_t(ranks), 0);
    std::vector<ParticlePlyRecord> out(own.size());
    for (std::size_t i = 0; i < own.size(); ++i) {
        out[i] = detail::particlePlyRecord(own, i, path);
        ++sendCounts[std::size_t(owner(out[i].id))];
    }
    for (int r = 1; r < ranks; ++r)
        sendOffsets[std::size_t(r)] =
            sendOffsets[std::size_t(r - 1)] + sendCounts[std::size_t(r - 1)];
    {
        std::vector<ParticlePlyRecord> byOwner(out.size());
        std::vector<int> fill = sendOffsets;
        for (const ParticlePlyRecord& v : out)
            byOwner[std::size_t(fill[std::size_t(owner(v.id))]++)] = v;
        out.swap(byOwner);
    }
    MPI_Datatype vertex;
    MPI_Type_contiguous(int(sizeof(ParticlePlyRecord)), MPI_BYTE, &vertex);
    MPI_Type_commit(&vertex);
    MPI_Alltoall(sendCounts.data(), 1, MPI_INT, receiveCounts.data(), 1, MPI_INT, comm);
    for (int r = 1; r < ranks; ++r)
        receiveOffsets[std::size_t(r)] =
            receiveOffsets[std::size_t(r - 1)] + receiveCounts[std::size_t(r - 1)];
    std::vector<ParticlePlyRecord> mine(std::size_t(receiveOffsets.back()) +
                                        std::size_t(receiveCounts.back()));
    const int exchanged =
        MPI_Alltoallv(out.data(), sendCounts.data(), sendOffsets.data(), vertex, mine.data(),
                      receiveCounts.data(), receiveOffsets.data(), vertex, comm);
    std::vector<ParticlePlyRecord>().swap(out);
    if (exchanged != MPI_SUCCESS) MPI_Type_free(&vertex);
    agree(exchanged, path, "sending the particles to their id ranges", comm);
    std::sort(mine.begin(), mine.end(),
              [](const ParticlePlyRecord& a, const ParticlePlyRecord& b) { return a.id < b.id; });

    // This rank's first vertex: after the header and the ranks before it.
    const std::uint64_t before = distributed::sumOverRanksBefore(mine.size());
    const std::uint64_t total = distributed::sumOverRanks(mine.size());
    const std::string header =
        detail::plyHeader(detail::kParticlePlyComment, detail::kParticlePlyProperties, total);
    const std::filesystem::path temporary =
        path.parent_path() / ("." + path.filename().string() + ".tmp-ranks");
    MPI_File file;
    const int opened = MPI_File_open(comm, temporary.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY,
                                     MPI_INFO_NULL, &file);
    if (opened != MPI_SUCCESS) MPI_Type_free(&vertex);
    agree(opened, path, "creating the file", comm);
    int written = MPI_File_set_size(file, 0);  // a temporary a killed run left
    if (written == MPI_SUCCESS && rank == 0)
        written = MPI_File_write_at(file, 0, header.data(), int(header.size()), MPI_CHAR,
                                    MPI_STATUS_IGNORE);
    // In pieces of at most 2^30 vertices (MPI counts are int); every rank
    // takes part in each round of the collective write.
    constexpr std::uint64_t kPiece = std::uint64_t{1} << 30;
    unsigned long long rounds = (mine.size() + kPiece - 1) / kPiece;
    MPI_Allreduce(MPI_IN_PLACE, &rounds, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, comm);
    for (unsigned long long k = 0; k < rounds; ++k) {
        const std::uint64_t at = std::min<std::uint64_t>(k * kPiece, mine.size());
        const std::uint64_t n = std::min<std::uint64_t>(kPiece, mine.size() - at);
        const auto offset = MPI_Offset(header.size() + (before + at) * sizeof(ParticlePlyRecord));
        const int code = MPI_File_write_at_all(file, offset, mine.data() + at, int(n), vertex,
                                               MPI_STATUS_IGNORE);
        if (written == MPI_SUCCESS) written = code;
    }
    if (written == MPI_SUCCESS) written = MPI_File_sync(file);
    const int closed = MPI_File_close(&file);
    if (written == MPI_SUCCESS) written = closed;
    MPI_Type_free(&vertex);
    try {
        agree(written, path, "writing (disk full?)", comm);
    } catch (const IoError&) {
        if (rank == 0) {
            std::error_code ignored;
            std::filesystem::remove(temporary, ignored);
        }
        throw;
    }
    std::error_code renamed;
    if (rank == 0) std::filesystem::rename(temporary, path, renamed);
    if (distributed::anyRank(bool(renamed)))
        throw IoError(path.string() + ": cannot rename the temporary file into place" +
                      (renamed ? ": " + renamed.message() : std::string()));
#else
    writeParticlesPly(path, own);
#endif
}

}  // namespace pbf
