// Distributed runs: one simulation split across MPI processes (ranks), on
// one machine or several (docs/distributed.md).
//
// `mpirun -np N pbf run scene.json` starts N copies of pbf; each calls
// initialize() first. Every rank builds the same World (solids, emitters
// and rigid bodies are replicated: they are small and every rank's fluid
// touches them) with the distributed backend (BackendKind::Mpi), which
// gives each rank a range of the cell key (a compact region of space) and
// exchanges the particles at the ranges' borders. Each rank creates its share
// of the initial particles; the particle frames (PLY, H5Part) and checkpoints
// are written by all ranks at once, the other files by rank 0.
//
// In a build without MPI (PBF_MPI off) or a process not started by an MPI
// launcher, there is one rank: rank() is 0, size() is 1, and nothing here
// talks to MPI.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pbf::distributed {

// Whether this build has MPI (CMake option PBF_MPI).
bool built();
// Whether an MPI launcher (mpirun, srun) started this process: its
// environment names a rank. Plain `pbf run` does not initialise MPI at all.
bool launched();
// Initialises MPI when launched() (threads: funneled, OpenMP runs between
// MPI calls). Throws std::runtime_error when launched by an MPI launcher in
// a build without MPI (N copies would each run the whole scene).
void initialize(int& argc, char**& argv);
// Ends MPI when initialize() started it; called at exit.
void finalize();
bool active();  // MPI initialised by initialize()
int rank();     // this process's rank (0 when not active)
int size();     // ranks in the run (1 when not active)
int ranksHere();  // ranks on this machine (sharing its memory; 1 when not active)
// Ends every rank of the job with `status` (MPI_Abort) after a failure on
// one rank that the others cannot learn of (they would wait for it forever).
[[noreturn]] void abort(int status);
// The same text on every rank: rank 0's `text` (a checkpoint read by rank 0).
std::string broadcast(const std::string& text);
// Whether `value` is true on any rank (every rank gets the answer): ranks
// that decide alone (a signal, a wall-clock checkpoint interval) must agree
// before they act, or one would wait forever in a collective the others skip.
bool anyRank(bool value);
// The largest `value` over ranks (every rank gets it).
double maxOverRanks(double value);
// Every rank's `value`, in rank order, on every rank (one entry in one process).
std::vector<double> valuesOfRanks(double value);
// The sum of `value` over all ranks, and over the ranks before this one
// (0 on rank 0); every rank gets its answer.
std::uint64_t sumOverRanks(std::uint64_t value);
std::uint64_t sumOverRanksBefore(std::uint64_t value);
// Waits until every rank gets here.
void barrier();

}  // namespace pbf::distributed
