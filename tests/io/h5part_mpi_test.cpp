// H5Part files written by MPI ranks together (src/io/h5part.cpp); run by
// tests/io/h5part_mpi_test.sh (ctest mpi.h5part_ranks) under mpirun.
//
//   pbf_h5part_mpi_test write OUT      (under mpirun, any number of ranks)
//     Every rank writes its part of one step of 1003 particles (uneven
//     parts; with several ranks, rank 1 holds none) to OUT/frame_00012.h5part.
//     Rank 0 reads it back and compares it with the whole set, and writes the
//     whole set alone, over MPI_COMM_SELF and through HDF5's serial driver:
//     the same datasets. A missing directory, and an id past 2^63 - 1 on one
//     rank only, throw the same IoError on every rank; parts that do not
//     tile the step are refused on every rank; no temporary file is left.
//     The ranks write frame 13 too (time 0.45), and rank 0 the index
//     OUT/particles.h5part of frames 12 and 13, and OUT/expected.json (the
//     set, frame and times) for the ParaView test
//     (tests/clients/paraview_h5part_test.py).
//   pbf_h5part_mpi_test compare A B    (one process, no MPI)
//     The two files hold the same step, time and datasets.
//   pbf_h5part_mpi_test matches-ply H5PART PLY    (one process, no MPI)
//     A run's H5Part frame, sorted by id, holds the PLY frame's particles.
// Prints "PASS" (rank 0) when every check held; exits 1 otherwise.
#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf/io/h5part.hpp"

namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kTotal = 1003;
constexpr int kFrame = 12;
constexpr double kTime = 0.4;
constexpr double kNextTime = 0.45;  // frame 13's, in the index

int failures = 0;

void check(bool condition, const std::string& message) {
    if (condition) return;
    ++failures;
    std::fprintf(stderr, "FAIL: %s\n", message.c_str());
}

// Particle g of the step: every field distinct, ids past 2^32 and not in
// file order.
void setParticle(pbf::ParticleStore& p, std::size_t k, std::uint64_t g) {
    const float f = float(g);
    p.position.set(k, {0.001f * f, 0.5f - 0.0003f * f, 0.25f + 0.002f * float(g % 17)});
    p.velocity.set(k, {0.1f * float(g % 7), -0.01f * f, 1.0f / (1.0f + f)});
    p.density[k] = 990.0f + 0.01f * f;
    p.id[k] = 7'000'000'000ull + (g * 7919) % kTotal;
}

pbf::ParticleStore particles(std::uint64_t first, std::uint64_t count) {
    pbf::ParticleStore p;
    p.resize(count);
    for (std::uint64_t k = 0; k < count; ++k) setParticle(p, k, first + k);
    return p;
}

// Rank r's part [cut(r), cut(r + 1)): weights 1, 0, 3, 4, 5, ... (rank 1
// none, the others uneven); one rank holds everything.
std::uint64_t cut(int rank, int ranks) {
    if (ranks == 1) return rank == 0 ? 0 : kTotal;
    const auto weight = [](int r) -> std::uint64_t { return r == 1 ? 0 : std::uint64_t(r) + 1; };
    std::uint64_t below = 0, all = 0;
    for (int r = 0; r < ranks; ++r) {
        all += weight(r);
        if (r < rank) below += weight(r);
    }
    return kTotal * below / all;
}

void checkEqual(const pbf::H5PartFrame& a, const pbf::H5PartFrame& b, const std::string& what) {
    check(a.frame == b.frame && a.time == b.time, what + ": frame or time differs");
    const pbf::ParticleFrame &p = a.particles, &q = b.particles;
    check(p.position == q.position, what + ": positions differ");
    check(p.velocity == q.velocity, what + ": velocities differ");
    check(p.density == q.density, what + ": densities differ");
    check(p.id == q.id, what + ": ids differ");
}

// An H5Part frame of a run against its PLY frame (in id order).
void checkMatchesPly(const pbf::H5PartFrame& h5, const pbf::ParticleFrame& ply,
                     const std::string& what) {
    const pbf::ParticleFrame& f = h5.particles;
    check(f.id.size() == ply.id.size(), what + ": " + std::to_string(f.id.size()) +
                                            " particles, the PLY frame " +
                                            std::to_string(ply.id.size()));
    if (f.id.size() != ply.id.size() || f.velocity.size() != f.id.size() ||
        f.density.size() != f.id.size())
        return;
    std::vector<std::size_t> order(f.id.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return f.id[a] < f.id[b]; });
    for (std::size_t k = 0; k < order.size() && failures <= 10; ++k) {
        const std::size_t i = order[k];
        check(f.id[i] == ply.id[k] && f.position[i] == ply.position[k] &&
                  f.velocity[i] == ply.velocity[k] && f.density[i] == ply.density[k],
              what + ": the particle with id " + std::to_string(f.id[i]) + " differs");
    }
}

// The read-back file against the whole set.
void checkWholeSet(const pbf::H5PartFrame& frame, const std::string& what) {
    const pbf::ParticleStore all = particles(0, kTotal);
    check(frame.frame == kFrame, what + ": frame " + std::to_string(frame.frame.value_or(-1)));
    check(frame.time == kTime, what + ": no TimeValue " + std::to_string(kTime));
    const pbf::ParticleFrame& f = frame.particles;
    if (f.position.size() != kTotal || f.velocity.size() != kTotal || f.density.size() != kTotal ||
        f.id.size() != kTotal) {
        check(false, what + ": " + std::to_string(f.position.size()) + " particles, expected " +
                         std::to_string(kTotal) + " with every field");
        return;
    }
    for (std::size_t i = 0; i < kTotal; ++i) {
        check(f.position[i] == all.position.get(i) && f.velocity[i] == all.velocity.get(i) &&
                  f.density[i] == all.density[i] && f.id[i] == all.id[i],
              what + ": particle " + std::to_string(i) + " differs from the concatenated parts");
        if (failures > 10) return;
    }
}

// The same IoError on every rank, starting with `prefix`; else a failure.
template <class Write>
void expectSameErrorEverywhere(int rank, const std::string& prefix, Write&& write,
                               const std::string& what) {
    std::string message;
    try {
        write();
        check(false, what + ": no error on rank " + std::to_string(rank));
    } catch (const pbf::IoError& e) {
        message = e.what();
    }
    check(message.rfind(prefix, 0) == 0, what + ": rank " + std::to_string(rank) + " says '" +
                                             message + "', expected it to start with '" + prefix +
                                             "'");
    // Rank 0's message, character by character, on every rank.
    unsigned long long length = message.size();
    MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
    std::string first = rank == 0 ? message : std::string(length, '\0');
    MPI_Bcast(first.data(), int(length), MPI_CHAR, 0, MPI_COMM_WORLD);
    check(first == message, what + ": rank " + std::to_string(rank) + " says '" + message +
                                "', rank 0 '" + first + "'");
}

void writeExpected(const fs::path& path) {
    const pbf::ParticleStore all = particles(0, kTotal);
    std::ofstream out(path);
    out << std::setprecision(17) << "{\"frame\": " << kFrame << ", \"time\": " << kTime
        << ", \"index_times\": [" << kTime << ", " << kNextTime << "], \"particles\": " << kTotal
        << std::setprecision(9);
    const auto column = [&](const char* name, auto value) {
        out << ",\n \"" << name << "\": [";
        for (std::size_t i = 0; i < kTotal; ++i) out << (i ? ", " : "") << value(i);
        out << "]";
    };
    column("x", [&](std::size_t i) { return all.position.x[i]; });
    column("y", [&](std::size_t i) { return all.position.y[i]; });
    column("z", [&](std::size_t i) { return all.position.z[i]; });
    column("vx", [&](std::size_t i) { return all.velocity.x[i]; });
    column("vy", [&](std::size_t i) { return all.velocity.y[i]; });
    column("vz", [&](std::size_t i) { return all.velocity.z[i]; });
    column("density", [&](std::size_t i) { return all.density[i]; });
    column("id", [&](std::size_t i) { return all.id[i]; });
    out << "}\n";
    check(bool(out), path.string() + ": cannot write");
}

int write(const fs::path& out) {
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    const auto world = pbf::H5PartComm::mpi(MPI_Comm_c2f(MPI_COMM_WORLD));
    if (rank == 0) {
        fs::remove_all(out);
        fs::create_directories(out);
    }
    MPI_Barrier(MPI_COMM_WORLD);

    const std::uint64_t first = cut(rank, ranks), count = cut(rank + 1, ranks) - first;
    const pbf::ParticleStore part = particles(first, count);
    const fs::path file = out / "frame_00012.h5part";
    pbf::writeH5PartFile(file, kFrame, kTime, part, first, kTotal, world);
    pbf::writeH5PartFile(out / "frame_00013.h5part", kFrame + 1, kNextTime, part, first, kTotal,
                         world);

    // A missing directory: every rank throws, the same message.
    const fs::path missing = out / "no_such_directory" / "frame_00001.h5part";
    expectSameErrorEverywhere(
        rank, missing.string() + ": cannot create file",
        [&] { pbf::writeH5PartFile(missing, 1, 0.0, part, first, kTotal, world); },
        "missing directory");
    // A failure on one rank only (the last one's first id does not fit int64):
    // every rank learns it from the agreement and throws, none hangs.
    pbf::ParticleStore bad = part;
    if (rank == ranks - 1 && bad.size() > 0) bad.id[0] = 1ull << 63;
    expectSameErrorEverywhere(
        rank, (out / "bad.h5part").string() + ": cannot write",
        [&] { pbf::writeH5PartFile(out / "bad.h5part", 1, 0.0, bad, first, kTotal, world); },
        "one rank's bad id");
    // Parts that do not tile the step: refused on every rank.
    bool refused = false;
    try {
        pbf::writeH5PartFile(out / "gap.h5part", 1, 0.0, part, first + (rank == ranks - 1 ? 1 : 0),
                             kTotal, world);
    } catch (const std::invalid_argument&) {
        refused = true;
    }
    check(refused, "parts with a gap: not refused on rank " + std::to_string(rank));

    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) {
        const pbf::H5PartFrame frame = pbf::readH5PartFile(file);
        checkWholeSet(frame, file.string());
        // The whole set from one rank: MPI-IO over MPI_COMM_SELF, and the
        // serial driver.
        const pbf::ParticleStore all = particles(0, kTotal);
        pbf::writeH5PartFile(out / "self.h5part", kFrame, kTime, all, 0, kTotal,
                             pbf::H5PartComm::mpi(MPI_Comm_c2f(MPI_COMM_SELF)));
        pbf::writeH5PartFile(out / "serial.h5part", kFrame, kTime, all, 0, kTotal,
                             pbf::H5PartComm::thisProcess());
        checkEqual(frame, pbf::readH5PartFile(out / "self.h5part"),
                   std::to_string(ranks) + " ranks against MPI_COMM_SELF");
        checkEqual(frame, pbf::readH5PartFile(out / "serial.h5part"),
                   std::to_string(ranks) + " ranks against the serial driver");
        const std::vector<fs::path> frames{"frame_00012.h5part", "frame_00013.h5part"};
        pbf::writeH5PartIndex(out / "particles.h5part", frames);
        checkEqual(frame, pbf::readH5PartFile(out / "particles.h5part"), "the index's Step#0");
        // Only the written files: no temporary left by any write or failure.
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(out))
            names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        const std::vector<std::string> expected{"frame_00012.h5part", "frame_00013.h5part",
                                                "particles.h5part", "self.h5part", "serial.h5part"};
        check(names == expected, "files left in " + out.string() + ": " +
                                     std::to_string(names.size()) + ", expected " +
                                     std::to_string(expected.size()));
        writeExpected(out / "expected.json");
    }

    int all = 0;
    MPI_Allreduce(&failures, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    if (rank == 0 && all == 0)
        std::printf("PASS: %d ranks wrote %s (parts of %llu..%llu particles)\n", ranks,
                    file.c_str(), static_cast<unsigned long long>(cut(1, ranks) - cut(0, ranks)),
                    static_cast<unsigned long long>(cut(ranks, ranks) - cut(ranks - 1, ranks)));
    return all == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    try {
        if (mode == "compare" && argc == 4) {
            checkEqual(pbf::readH5PartFile(argv[2]), pbf::readH5PartFile(argv[3]),
                       std::string(argv[2]) + " against " + argv[3]);
            if (failures == 0)
                std::printf("PASS: %s and %s hold the same step\n", argv[2], argv[3]);
            return failures == 0 ? 0 : 1;
        }
        if (mode == "matches-ply" && argc == 4) {
            checkMatchesPly(pbf::readH5PartFile(argv[2]), pbf::readParticlesPly(argv[3]),
                            std::string(argv[2]) + " against " + argv[3]);
            if (failures == 0)
                std::printf("PASS: %s holds the particles of %s\n", argv[2], argv[3]);
            return failures == 0 ? 0 : 1;
        }
        if (mode == "write" && argc == 3) {
            MPI_Init(&argc, &argv);
            const int status = write(argv[2]);
            MPI_Finalize();
            return status;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "FAIL: %s\n", e.what());
        int initialized = 0;
        MPI_Initialized(&initialized);
        if (initialized) MPI_Abort(MPI_COMM_WORLD, 1);  // the other ranks would wait
        return 1;
    }
    std::fprintf(stderr, "usage: %s write OUT | compare A B | matches-ply H5PART PLY\n", argv[0]);
    return 2;
}
