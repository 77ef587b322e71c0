// .pvd collections (include/pbf/io/vtk.hpp): the list of a series' files with
// their simulated times, which ParaView shows as its time steps.
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ostream>
#include <string>
#include <string_view>

#include "pbf/io/io.hpp"
#include "pbf/io/vtk.hpp"

namespace pbf::vtk {
namespace {

constexpr std::string_view kHead =
    "<?xml version=\"1.0\"?>\n<!-- written by pbf -->\n"
    "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
    "  <Collection>\n";
// What every collection ends with; appendToCollection writes over it.
constexpr std::string_view kTail = "  </Collection>\n</VTKFile>\n";

std::string escapeXml(std::string_view text) {
    std::string out;
    for (const char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

// The shortest text that reads back as the same double ({} in fmt), so the
// times in ParaView are exactly frame / fps.
std::string entryLine(const CollectionEntry& e) {
    return fmt::format("    <DataSet timestep=\"{}\" part=\"0\" file=\"{}\"/>\n", e.time,
                       escapeXml(e.file));
}

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& what) {
    const int error = errno;
    throw IoError(path.string() + ": " + what +
                  (error != 0 ? " (" + std::string(std::strerror(error)) + ")" : std::string()));
}

// Closes the descriptor on every path out of appendToCollection.
class FileDescriptor {
  public:
    explicit FileDescriptor(int fd) : fd_(fd) {}
    ~FileDescriptor() {
        if (fd_ >= 0) ::close(fd_);
    }
    FileDescriptor(const FileDescriptor&) = delete;
    FileDescriptor& operator=(const FileDescriptor&) = delete;
    int get() const { return fd_; }
    bool close() {
        const int fd = fd_;
        fd_ = -1;
        return ::close(fd) == 0;
    }

  private:
    int fd_;
};

}  // namespace

void writeCollection(const std::filesystem::path& path,
                     const std::vector<CollectionEntry>& entries) {
    writeFileAtomically(path, [&](std::ostream& out) {
        out << kHead;
        for (const CollectionEntry& e : entries) out << entryLine(e);
        out << kTail;
    });
}

void appendToCollection(const std::filesystem::path& path, const CollectionEntry& entry) {
    errno = 0;
    FileDescriptor fd(::open(path.c_str(), O_RDWR | O_CLOEXEC));
    if (fd.get() < 0) fail(path, "cannot open the collection to add a frame");
    struct stat info {};
    if (::fstat(fd.get(), &info) != 0) fail(path, "cannot read the collection's size");
    const auto size = static_cast<std::size_t>(info.st_size);
    std::string end(kTail.size(), '\0');
    errno = 0;
    if (size < kHead.size() + kTail.size() ||
        ::pread(fd.get(), end.data(), end.size(), static_cast<off_t>(size - kTail.size())) !=
            static_cast<::ssize_t>(end.size()) ||
        end != kTail)
        fail(path, "not a collection written by pbf (it does not end with </Collection>)");
    // One write over the closing tags: the file holds the old list or the new
    // one, as stats.csv holds whole rows (appendToFile).
    const std::string text = entryLine(entry) + std::string(kTail);
    errno = 0;
    const ::ssize_t written =
        ::pwrite(fd.get(), text.data(), text.size(), static_cast<off_t>(size - kTail.size()));
    if (written != static_cast<::ssize_t>(text.size())) fail(path, "write failed (disk full?)");
    if (!fd.close()) fail(path, "write failed when closing (disk full?)");
}

}  // namespace pbf::vtk
