// H5Part particle files (.h5part): one frame's particles in HDF5, written by
// every MPI rank of a distributed run at once (parallel HDF5 over MPI-IO,
// each rank its own range of every dataset), so no rank gathers the others'
// particles (docs/distributed.md, "Parallel output: H5Part").
//
// A file holds one group `Step#0` in the H5Part layout that ParaView's
// H5Part reader opens:
//   x, y, z      float32  position, metres (the coordinates the caller passes:
//                         World::particles() gives world coordinates)
//   vx, vy, vz   float32  velocity, m/s
//   density      float32  last density estimate, kg/m^3
//   id           int64    the particle's stable id (H5Part readers expect
//                         64-bit signed integers)
// one value per particle, the ranks' parts one after another in rank order
// (not sorted by id: the id dataset names each particle), and the group's
// attributes TimeValue (float64, seconds), which ParaView shows as the
// step's time, and Frame (int32, the frame's number). These are the PLY
// frames' fields (pbf/io/io.hpp). The group is Step#0 in every file, not
// Step#<frame>: ParaView's reader opens a file's steps by index from Step#0.
//
// Every file is written whole: to a temporary file beside it, renamed over
// it by rank 0 once every rank has finished, so a killed run never leaves a
// half-written frame. Needs a build with parallel HDF5 (CMake option
// PBF_HDF5, Debian's libhdf5-openmpi-dev); without it every function here
// throws IoError saying what to install.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>

#include "pbf/core/particles.hpp"
#include "pbf/io/io.hpp"

namespace pbf {

// The processes that write one file together.
struct H5PartComm {
    // This process alone, through HDF5's serial file driver: no MPI call, so
    // it works where MPI is not initialised (a run not started by mpirun).
    static H5PartComm thisProcess() { return {}; }
    // The ranks of an MPI communicator, given as its Fortran handle,
    // MPI_Comm_c2f(comm): MPI's portable integer for a communicator (MPI_Comm
    // itself is a pointer in Open MPI and an int in MPICH), so that this
    // header needs no <mpi.h>.
    static H5PartComm mpi(int fortranHandle) { return {true, fortranHandle}; }
    // The ranks of the run: MPI_COMM_WORLD when pbf::distributed started MPI
    // (pbf/core/distributed.hpp), thisProcess() otherwise.
    static H5PartComm run();

    bool usesMpi = false;
    int fortranHandle = 0;
};

// Whether this build writes and reads H5Part files (CMake option PBF_HDF5).
bool h5partBuilt();

// Writes frame `frame` to `file` (frame_00012.h5part) collectively: every
// rank of `comm` calls it with its own part. This rank's particles are entries
// [first, first + part.size()) of the step's `total` particles (the ranks'
// parts are contiguous and in rank order; a rank may hold none); `time` in
// seconds. Throws, on every rank alike so that none is left waiting in a
// collective call: IoError naming `file` when any rank fails (the directory
// is missing or not writable, HDF5 or MPI-IO fails; the message is the first
// failing rank's, and no temporary file is left), std::invalid_argument when
// the parts do not tile [0, total). Call from one thread at a time.
void writeH5PartFile(const std::filesystem::path& file, int frame, double time,
                     const ParticleStore& part, std::uint64_t first, std::uint64_t total,
                     H5PartComm comm);

// An index of a run's frame files for ParaView: `file` (particles.h5part)
// holds the groups Step#0, Step#1, ... as HDF5 external links to the Step#0
// of each of `frames` in turn (paths as stored, relative ones resolved from
// the index's directory). ParaView's H5Part reader opens one file, not a
// series of files, and shows its steps as time steps: opened on the index,
// it plays the whole run at the frames' TimeValues. Links only (64 kB for
// 1,000 frames), written whole by the calling process alone (rank 0 in a
// distributed run), after the frames it lists. Throws IoError naming `file`.
void writeH5PartIndex(const std::filesystem::path& file,
                      std::span<const std::filesystem::path> frames);

// A step of an H5Part file as read back; the attributes are absent from
// some other writers' files.
struct H5PartFrame {
    std::optional<int> frame;    // the Frame attribute
    std::optional<double> time;  // the TimeValue attribute, seconds
    ParticleFrame particles;     // in the file's order; velocity, density, id as present
};

// Reads a file written by writeH5PartFile in this process (serial HDF5; MPI
// need not be initialised), or another writer's H5Part file with x, y and z
// datasets (its lowest-numbered step when it holds several). Throws IoError
// naming the file.
H5PartFrame readH5PartFile(const std::filesystem::path& file);

}  // namespace pbf
