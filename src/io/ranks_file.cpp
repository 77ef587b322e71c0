#include "io/ranks_file.hpp"

#ifdef PBF_HAVE_MPI

#include <algorithm>
#include <system_error>
#include <utility>

#include "pbf/core/distributed.hpp"
#include "pbf/io/io.hpp"

namespace pbf::detail {
namespace {

constexpr std::uint64_t kPiece = std::uint64_t{1} << 30;  // bytes per MPI call (counts are int)

std::string mpiErrorText(int code) {
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    return std::string(text, std::size_t(length));
}

// The rounds of pieces every rank takes part in for the largest part.
unsigned long long roundsFor(std::uint64_t bytes) {
    unsigned long long rounds = (bytes + kPiece - 1) / kPiece;
    MPI_Allreduce(MPI_IN_PLACE, &rounds, 1, MPI_UNSIGNED_LONG_LONG, MPI_MAX, MPI_COMM_WORLD);
    return rounds;
}

}  // namespace

void agreeOnError(const std::string& error) {
    int first = error.empty() ? distributed::size() : distributed::rank();
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == distributed::size()) return;
    std::string message = error;
    int length = int(message.size());
    MPI_Bcast(&length, 1, MPI_INT, first, MPI_COMM_WORLD);
    message.resize(std::size_t(length));
    MPI_Bcast(message.data(), length, MPI_CHAR, first, MPI_COMM_WORLD);
    throw IoError(message);
}

void agreeOnResult(int code, const std::filesystem::path& path, const std::string& what) {
    agreeOnError(code == MPI_SUCCESS
                     ? std::string()
                     : path.string() + ": " + what + " failed on rank " +
                           std::to_string(distributed::rank()) + " (" + mpiErrorText(code) + ")");
}

RanksFileWriter::RanksFileWriter(std::filesystem::path path)
    : path_(std::move(path)),
      temporary_(path_.parent_path() / ("." + path_.filename().string() + ".tmp-ranks")) {
    int code = MPI_File_open(MPI_COMM_WORLD, temporary_.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY,
                             MPI_INFO_NULL, &file_);
    agreeOnResult(
        code, path_,
        "creating the file (is the directory writable, and on a file system every rank sees?)");
    code = MPI_File_set_size(file_, 0);  // a temporary file a killed run left
    if (code != MPI_SUCCESS) error_ = code;
}

RanksFileWriter::~RanksFileWriter() {
    if (file_ == MPI_FILE_NULL) return;
    MPI_File_close(&file_);
    if (distributed::rank() == 0) {
        std::error_code ignored;
        std::filesystem::remove(temporary_, ignored);
    }
}

void RanksFileWriter::writeAt(std::uint64_t offset, const void* data, std::uint64_t bytes) {
    for (std::uint64_t at = 0; at < bytes && error_ == MPI_SUCCESS; at += kPiece) {
        const int code =
            MPI_File_write_at(file_, MPI_Offset(offset + at), static_cast<const char*>(data) + at,
                              int(std::min(kPiece, bytes - at)), MPI_BYTE, MPI_STATUS_IGNORE);
        if (code != MPI_SUCCESS) error_ = code;
    }
}

void RanksFileWriter::writeAtAll(std::uint64_t offset, const void* data, std::uint64_t bytes) {
    const unsigned long long rounds = roundsFor(bytes);
    for (unsigned long long k = 0; k < rounds; ++k) {
        const std::uint64_t at = std::min<std::uint64_t>(k * kPiece, bytes);
        const std::uint64_t n = std::min(kPiece, bytes - at);
        const int code = MPI_File_write_at_all(file_, MPI_Offset(offset + at),
                                               static_cast<const char*>(data) + at, int(n),
                                               MPI_BYTE, MPI_STATUS_IGNORE);
        if (code != MPI_SUCCESS && error_ == MPI_SUCCESS) error_ = code;
    }
}

void RanksFileWriter::commit() {
    int code = error_ == MPI_SUCCESS ? MPI_File_sync(file_) : error_;
    const int closed = MPI_File_close(&file_);
    file_ = MPI_FILE_NULL;
    if (code == MPI_SUCCESS) code = closed;
    try {
        agreeOnResult(code, path_, "writing (disk full?)");
    } catch (const IoError&) {
        if (distributed::rank() == 0) {
            std::error_code ignored;
            std::filesystem::remove(temporary_, ignored);
        }
        throw;
    }
    std::error_code renamed;
    if (distributed::rank() == 0) std::filesystem::rename(temporary_, path_, renamed);
    if (distributed::anyRank(bool(renamed)))
        throw IoError(path_.string() + ": cannot rename the temporary file into place" +
                      (renamed ? ": " + renamed.message() : std::string()));
}

RanksFileReader::RanksFileReader(const std::filesystem::path& path) : path_(path) {
    const int code =
        MPI_File_open(MPI_COMM_WORLD, path_.c_str(), MPI_MODE_RDONLY, MPI_INFO_NULL, &file_);
    agreeOnResult(code, path_, "opening the file");
}

RanksFileReader::~RanksFileReader() {
    if (file_ != MPI_FILE_NULL) MPI_File_close(&file_);
}

void RanksFileReader::readAtAll(std::uint64_t offset, void* data, std::uint64_t bytes,
                                const std::string& what) {
    const unsigned long long rounds = roundsFor(bytes);
    int error = MPI_SUCCESS;
    for (unsigned long long k = 0; k < rounds; ++k) {
        const std::uint64_t at = std::min<std::uint64_t>(k * kPiece, bytes);
        const std::uint64_t n = std::min(kPiece, bytes - at);
        MPI_Status status;
        int code = MPI_File_read_at_all(file_, MPI_Offset(offset + at),
                                        static_cast<char*>(data) + at, int(n), MPI_BYTE, &status);
        int count = 0;
        if (code == MPI_SUCCESS) MPI_Get_count(&status, MPI_BYTE, &count);
        if (code == MPI_SUCCESS && std::uint64_t(count) != n) code = MPI_ERR_TRUNCATE;
        if (code != MPI_SUCCESS && error == MPI_SUCCESS) error = code;
    }
    agreeOnResult(error, path_, "reading " + what);
}

}  // namespace pbf::detail

#endif
