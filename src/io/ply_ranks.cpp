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

#include "io/ranks_file.hpp"
#endif

namespace pbf {

void writeParticlesPlyFromRanks(const std::filesystem::path& path, const ParticleStore& own) {
    if (distributed::size() == 1) {
        writeParticlesPly(path, own);
        return;
    }
#ifdef PBF_HAVE_MPI
    using detail::ParticlePlyRecord;
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
    for (std::uint64_t id : own.id) ++sendCounts[std::size_t(owner(std::uint32_t(id)))];
    for (int r = 1; r < ranks; ++r)
        sendOffsets[std::size_t(r)] =
            sendOffsets[std::size_t(r - 1)] + sendCounts[std::size_t(r - 1)];
    std::vector<ParticlePlyRecord> out(own.size());
    {
        std::vector<int> fill = sendOffsets;
        for (std::size_t i = 0; i < own.size(); ++i)
            out[std::size_t(fill[std::size_t(owner(std::uint32_t(own.id[i])))]++)] =
                detail::particlePlyRecord(own, i, path);
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
    MPI_Type_free(&vertex);
    std::vector<ParticlePlyRecord>().swap(out);
    detail::agreeOnResult(exchanged, path, "sending the particles to their id ranges");
    std::sort(mine.begin(), mine.end(),
              [](const ParticlePlyRecord& a, const ParticlePlyRecord& b) { return a.id < b.id; });

    // This rank's first vertex: after the header and the ranks before it.
    const std::uint64_t before = distributed::sumOverRanksBefore(mine.size());
    const std::uint64_t total = distributed::sumOverRanks(mine.size());
    const std::string header =
        detail::plyHeader(detail::kParticlePlyComment, detail::kParticlePlyProperties, total);
    detail::RanksFileWriter file(path);
    if (rank == 0) file.writeAt(0, header.data(), header.size());
    file.writeAtAll(header.size() + before * sizeof(ParticlePlyRecord), mine.data(),
                    mine.size() * sizeof(ParticlePlyRecord));
    file.commit();
#else
    writeParticlesPly(path, own);
#endif
}

}  // namespace pbf
