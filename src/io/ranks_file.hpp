// One file written or read by all ranks of a distributed run at once, with
// MPI-IO (private header; only in builds with MPI, PBF_HAVE_MPI). The
// writers of the PLY frames (ply_ranks.cpp) and the checkpoints
// (checkpoint_ranks.cpp) use it.
//
// Every call marked collective must be made by every rank of
// MPI_COMM_WORLD in the same order. Failures become IoError on every rank at
// once (each collective stage ends in an agreement: an MPI_Allreduce of the
// ranks' outcomes), so no rank is left waiting in a collective call that the
// others skipped.
#pragma once

#ifdef PBF_HAVE_MPI

#include <mpi.h>

#include <cstdint>
#include <filesystem>
#include <string>

namespace pbf::detail {

// Collective: throws IoError on every rank when `error` is not empty on any,
// with the lowest such rank's `error` as the message.
void agreeOnError(const std::string& error);
// Collective: throws IoError on every rank when `code` is not MPI_SUCCESS on
// any, "<path>: <what> failed on rank R (<reason>)".
void agreeOnResult(int code, const std::filesystem::path& path, const std::string& what);

// Writes `path` whole: into a temporary file beside it, renamed over it by
// rank 0 when every rank has written its part (commit()); a writer
// destroyed before commit() leaves no temporary file.
class RanksFileWriter {
  public:
    explicit RanksFileWriter(std::filesystem::path path);  // collective
    RanksFileWriter(const RanksFileWriter&) = delete;
    RanksFileWriter& operator=(const RanksFileWriter&) = delete;
    ~RanksFileWriter();  // collective when commit() was not reached

    // This rank alone writes `bytes` at `offset`.
    void writeAt(std::uint64_t offset, const void* data, std::uint64_t bytes);
    // Collective: each rank writes its `bytes` at its `offset` (any size:
    // pieces of at most 1 GiB, in rounds every rank takes part in).
    void writeAtAll(std::uint64_t offset, const void* data, std::uint64_t bytes);
    // Collective: synced, closed and renamed into place; throws IoError on
    // every rank when any rank's write failed.
    void commit();

  private:
    std::filesystem::path path_, temporary_;
    MPI_File file_ = MPI_FILE_NULL;
    int error_ = MPI_SUCCESS;  // the first failed write's code on this rank
};

// Reads parts of an existing file on every rank.
class RanksFileReader {
  public:
    explicit RanksFileReader(const std::filesystem::path& path);  // collective
    RanksFileReader(const RanksFileReader&) = delete;
    RanksFileReader& operator=(const RanksFileReader&) = delete;
    ~RanksFileReader();  // collective
    // Collective: each rank reads its `bytes` at its `offset`; throws
    // IoError on every rank when any read failed or came back short.
    void readAtAll(std::uint64_t offset, void* data, std::uint64_t bytes, const std::string& what);

  private:
    std::filesystem::path path_;
    MPI_File file_ = MPI_FILE_NULL;
};

}  // namespace pbf::detail

#endif
