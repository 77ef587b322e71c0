#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <random>

#include "pbf/io.hpp"

namespace pbf {
namespace {

std::string describe(const std::filesystem::path& path, const std::string& what) {
    return path.string() + ": " + what;
}

// fsync so that the rename publishes complete data even after a power loss.
void syncFile(const std::filesystem::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

}  // namespace

void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write) {
    std::random_device random;
    const std::filesystem::path temporary =
        path.parent_path() /
        ("." + path.filename().string() + ".tmp" + std::to_string(random() % 1000000));
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) throw IoError(describe(path, "cannot create file (is the directory writable?)"));
        write(out);
        out.flush();
        if (!out) {
            out.close();
            std::error_code ignored;
            std::filesystem::remove(temporary, ignored);
            throw IoError(describe(path, "write failed (disk full?)"));
        }
    }
    syncFile(temporary);
    std::error_code ec;
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
        std::filesystem::remove(temporary, ec);
        throw IoError(describe(path, "cannot rename temporary file into place: " + ec.message()));
    }
}

}  // namespace pbf
