// MPI start-up and the few collective helpers the drivers need
// (include/pbf/core/distributed.hpp). Without PBF_HAVE_MPI, one rank.
#include "pbf/core/distributed.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

#ifdef PBF_HAVE_MPI
#include <mpi.h>
#endif

namespace pbf::distributed {
namespace {
bool started = false;
}

bool built() {
#ifdef PBF_HAVE_MPI
    return true;
#else
    return false;
#endif
}

bool launched() {
    // Open MPI's mpirun, PMIx launchers (srun --mpi=pmix) and PMI-1/2 (srun
    // with MPICH-style PMI) each name the rank in the environment.
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
        if (std::getenv(name)) return true;
    return false;
}

void initialize(int& argc, char**& argv) {
    if (!launched()) return;
#ifdef PBF_HAVE_MPI
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    // Errors come back as codes that pbf turns into messages naming the
    // call, instead of Open MPI's default of aborting the job silently.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    started = true;
#else
    (void)argc;
    (void)argv;
    const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
    if (size && std::string(size) != "1")
        throw std::runtime_error(
            "this pbf was built without MPI (PBF_MPI=OFF) but was started by an MPI launcher "
            "with " +
            std::string(size) +
            " ranks: each would run the whole scene. Rebuild with libopenmpi-dev installed "
            "(cmake -DPBF_MPI=ON) or run pbf without mpirun");
#endif
}

void finalize() {
#ifdef PBF_HAVE_MPI
    if (started) {
        int finalized = 0;
        MPI_Finalized(&finalized);
        if (!finalized) MPI_Finalize();
    }
#endif
    started = false;
}

bool active() {
    return started;
}

int rank() {
#ifdef PBF_HAVE_MPI
    if (started) {
        int r = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &r);
        return r;
    }
#endif
    return 0;
}

int size() {
#ifdef PBF_HAVE_MPI
    if (started) {
        int n = 1;
        MPI_Comm_size(MPI_COMM_WORLD, &n);
        return n;
    }
#endif
    return 1;
}

int ranksHere() {
#ifdef PBF_HAVE_MPI
    if (started) {
        MPI_Comm node;
        MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
        int n = 1;
        MPI_Comm_size(node, &n);
        MPI_Comm_free(&node);
        return n;
    }
#endif
    return 1;
}

void abort(int status) {
#ifdef PBF_HAVE_MPI
    if (started) MPI_Abort(MPI_COMM_WORLD, status);
#endif
    std::exit(status);
}

std::string broadcast(const std::string& text) {
#ifdef PBF_HAVE_MPI
    if (started) {
        unsigned long long length = text.size();
        MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
        std::string out = rank() == 0 ? text : std::string(length, '\0');
        // In pieces: MPI counts are int.
        constexpr unsigned long long kPiece = 1ull << 30;
        for (unsigned long long at = 0; at < length; at += kPiece)
            MPI_Bcast(out.data() + at, int(std::min(kPiece, length - at)), MPI_BYTE, 0,
                      MPI_COMM_WORLD);
        return out;
    }
#endif
    return text;
}

bool anyRank(bool value) {
#ifdef PBF_HAVE_MPI
    if (started) {
        int mine = value ? 1 : 0, any = 0;
        MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
        return any != 0;
    }
#endif
    return value;
}

double maxOverRanks(double value) {
#ifdef PBF_HAVE_MPI
    if (started) {
        double most = value;
        MPI_Allreduce(&value, &most, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        return most;
    }
#endif
    return value;
}

std::vector<double> valuesOfRanks(double value) {
#ifdef PBF_HAVE_MPI
    if (started) {
        std::vector<double> all(static_cast<std::size_t>(size()));
        MPI_Allgather(&value, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, MPI_COMM_WORLD);
        return all;
    }
#endif
    return {value};
}

std::uint64_t sumOverRanks(std::uint64_t value) {
#ifdef PBF_HAVE_MPI
    if (started) {
        unsigned long long mine = value, total = 0;
        MPI_Allreduce(&mine, &total, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
        return total;
    }
#endif
    return value;
}

std::uint64_t sumOverRanksBefore(std::uint64_t value) {
#ifdef PBF_HAVE_MPI
    if (started) {
        unsigned long long mine = value, before = 0;
        MPI_Exscan(&mine, &before, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
        return rank() == 0 ? 0 : before;  // MPI_Exscan leaves rank 0's undefined
    }
#endif
    (void)value;
    return 0;
}

void barrier() {
#ifdef PBF_HAVE_MPI
    if (started) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

}  // namespace pbf::distributed
