#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>

#include "pbf/io/io.hpp"

namespace pbf {
namespace {

std::string describe(const std::filesystem::path& path, const std::string& what) {
    return path.string() + ": " + what;
}

// The reason of the last failed system call, e.g. " (No space left on device)".
std::string lastError() {
    const int error = errno;
    return error != 0 ? " (" + std::string(std::strerror(error)) + ")" : std::string();
}

// fsync so that the rename publishes complete data even after a power loss.
// Some file systems (NFS, quotas) report a full disk only here.
bool syncFile(const std::filesystem::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return true;  // cannot sync; the data was written
    const bool ok = ::fsync(fd) == 0;
    return ::close(fd) == 0 && ok;
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write) {
    std::random_device random;
    const std::filesystem::path temporary =
        path.parent_path() /
        ("." + path.filename().string() + ".tmp" + std::to_string(random() % 1000000));
    {
        errno = 0;
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out)
            throw IoError(
                describe(path, "cannot create file (is the directory writable?)" + lastError()));
        errno = 0;
        try {
            write(out);
        } catch (...) {
            // The writer gave up: the old file stays as it was, and no
            // temporary is left beside it.
            out.close();
            std::error_code ignored;
            std::filesystem::remove(temporary, ignored);
            throw;
        }
        out.flush();
        if (!out) {
            const std::string reason = lastError();
            out.close();
            std::error_code ignored;
            std::filesystem::remove(temporary, ignored);
            throw IoError(describe(path, "write failed (disk full?)" + reason));
        }
    }
    errno = 0;
    if (!syncFile(temporary)) {
        const std::string reason = lastError();
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw IoError(describe(path, "write failed when syncing to disk (disk full?)" + reason));
    }
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
        const std::string reason = ec.message();  // before remove() overwrites ec
        std::filesystem::remove(temporary, ec);
        throw IoError(describe(path, "cannot rename temporary file into place: " + reason));
    }
}

void appendToFile(const std::filesystem::path& path, std::string_view text) {
    errno = 0;
    const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw IoError(describe(path, "cannot open for appending" + lastError()));
    // One write: a regular file takes it whole or (disk full) reports a short write.
    errno = 0;
    const ::ssize_t written = ::write(fd, text.data(), text.size());
    const std::string reason = lastError();
    const bool closed = ::close(fd) == 0;
    if (written != static_cast<::ssize_t>(text.size()) || !closed)
        throw IoError(describe(path, "write failed (disk full?)" + reason));
}

}  // namespace pbf
