#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>

#include "pbf/io.hpp"

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
        write(out);
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
        std::filesystem::remove(temporary, ec);
        throw IoError(describe(path, "cannot rename temporary file into place: " + ec.message()));
    }
}

}  // namespace pbf
