// H5Part files with parallel HDF5 (include/pbf/io/h5part.hpp).
//
// Every HDF5 call that touches the file's metadata or data is collective
// over the writing ranks, so a rank that fails alone must not return early:
// the others would wait for it forever. Each collective stage therefore ends
// in agree(), one MPI_Allreduce of the ranks' outcomes; when any rank failed,
// every rank throws the same IoError (the first failing rank's message) and
// unwinds the same handles.
#include "pbf/io/h5part.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cstring>
#include <limits>
#include <new>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "pbf/core/distributed.hpp"

namespace pbf {
namespace {

namespace fs = std::filesystem;

// An HDF5 object closed when it goes out of scope (handles close in the
// reverse order of their opening: datasets, group, file).
class H5Handle {
  public:
    H5Handle(hid_t id, herr_t (*closer)(hid_t)) : id_(id), close_(closer) {}
    H5Handle(const H5Handle&) = delete;
    H5Handle& operator=(const H5Handle&) = delete;
    ~H5Handle() { close(); }

    hid_t get() const { return id_; }
    bool valid() const { return id_ >= 0; }
    // Closes now; false when HDF5 reports a failure (closing the file
    // writes its last metadata).
    bool close() {
        const bool ok = id_ < 0 || close_(id_) >= 0;
        id_ = H5I_INVALID_HID;
        return ok;
    }

  private:
    hid_t id_;
    herr_t (*close_)(hid_t);
};

// HDF5 prints its error stack to stderr by default; pbf reports failures as
// IoError instead. Switched off for the duration of one call, then restored.
class QuietHdf5 {
  public:
    QuietHdf5() {
        H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    }
    QuietHdf5(const QuietHdf5&) = delete;
    QuietHdf5& operator=(const QuietHdf5&) = delete;
    ~QuietHdf5() { H5Eset_auto2(H5E_DEFAULT, function_, data_); }

  private:
    H5E_auto2_t function_ = nullptr;
    void* data_ = nullptr;
};

// The innermost entry of HDF5's error stack, the most specific one (e.g.
// "unable to open file: name = '...', errno = 2, error message = 'No such
// file or directory', ..."); clears the stack.
std::string hdf5Reason() {
    std::string reason;
    H5Ewalk2(
        H5E_DEFAULT, H5E_WALK_DOWNWARD,
        [](unsigned, const H5E_error2_t* error, void* out) -> herr_t {
            if (error->desc && *error->desc) *static_cast<std::string*>(out) = error->desc;
            return 0;
        },
        &reason);
    H5Eclear2(H5E_DEFAULT);
    return reason.empty() ? "HDF5 gave no reason" : reason;
}

// The ranks writing one file, or this process alone (no MPI call then).
class Writers {
  public:
    Writers(H5PartComm comm, const fs::path& file)
        : file_(file),
          mpi_(comm.usesMpi),
          comm_(comm.usesMpi ? MPI_Comm_f2c(comm.fortranHandle) : MPI_COMM_NULL) {
        if (!mpi_) return;
        check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
        check(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
    }

    bool mpi() const { return mpi_; }
    MPI_Comm comm() const { return comm_; }
    int rank() const { return rank_; }
    int size() const { return size_; }

    // Every rank's (first, count), in rank order.
    std::vector<std::array<std::uint64_t, 2>> gatherParts(std::uint64_t first,
                                                          std::uint64_t count) const {
        const std::array<std::uint64_t, 2> mine{first, count};
        std::vector<std::array<std::uint64_t, 2>> all(std::size_t(size_), mine);
        if (mpi_)
            check(MPI_Allgather(mine.data(), 2, MPI_UINT64_T, all.data(), 2, MPI_UINT64_T, comm_),
                  "MPI_Allgather");
        return all;
    }

    // Throws IoError "<file>: <what> (<reason>)" on every rank when `ok` is
    // false on any; the reason is that of the lowest failing rank, which
    // names itself when there are several ranks. Returns when all succeeded.
    void agree(bool ok, const std::string& what, const std::string& reason) const {
        int failing = ok ? size_ : rank_;
        if (mpi_) {
            const int mine = failing;
            check(MPI_Allreduce(&mine, &failing, 1, MPI_INT, MPI_MIN, comm_), "MPI_Allreduce");
        }
        if (failing == size_) return;
        std::string text = failing == rank_ ? reason : std::string();
        if (mpi_) text = broadcast(text, failing);
        const std::string where = size_ > 1 ? " on rank " + std::to_string(failing) : "";
        throw IoError(file_.string() + ": " + what + where + " (" + text + ")");
    }
    // agree() after an HDF5 call: the reason is HDF5's own.
    void agreeHdf5(bool ok, const std::string& what) const {
        agree(ok, what, ok ? std::string() : hdf5Reason());
    }

    // `text` as rank `root` has it.
    std::string broadcast(const std::string& text, int root) const {
        if (!mpi_) return text;
        unsigned long long length = text.size();
        check(MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, root, comm_), "MPI_Bcast");
        std::string out = rank_ == root ? text : std::string(length, '\0');
        if (length > 0)
            check(MPI_Bcast(out.data(), int(length), MPI_CHAR, root, comm_), "MPI_Bcast");
        return out;
    }

  private:
    // An MPI failure here is the communicator's, so every rank sees it.
    void check(int code, const char* call) const {
        if (code == MPI_SUCCESS) return;
        char text[MPI_MAX_ERROR_STRING];
        int length = 0;
        MPI_Error_string(code, text, &length);
        throw IoError(file_.string() + ": " + call + " failed (" + std::string(text, length) + ")");
    }

    const fs::path& file_;
    bool mpi_;
    MPI_Comm comm_;
    int rank_ = 0;
    int size_ = 1;
};

// The parts must tile [0, total) in rank order: checked on every rank from
// the same gathered values, so all throw or none does.
void checkParts(const Writers& ranks, const fs::path& file, std::uint64_t first,
                std::uint64_t count, std::uint64_t total) {
    std::uint64_t next = 0;
    for (const auto& [start, n] : ranks.gatherParts(first, count)) {
        if (start != next || n > total - std::min(total, start))
            throw std::invalid_argument(
                file.string() + ": the ranks' parts do not tile the step's " +
                std::to_string(total) + " particles in rank order (a part starts at " +
                std::to_string(start) + " with " + std::to_string(n) + " particles, expected " +
                std::to_string(next) + ")");
        next = start + n;
    }
    if (next != total)
        throw std::invalid_argument(file.string() + ": the ranks' parts hold " +
                                    std::to_string(next) + " particles, not the step's " +
                                    std::to_string(total));
}

// A name beside `file` that rank 0 draws and every rank uses.
fs::path temporaryName(const Writers& ranks, const fs::path& file) {
    std::string suffix;
    if (ranks.rank() == 0) suffix = std::to_string(std::random_device()() % 1000000);
    suffix = ranks.broadcast(suffix, 0);
    return file.parent_path() / ("." + file.filename().string() + ".tmp" + suffix);
}

// fsync, so that the rename publishes complete data after a power loss too.
bool syncFile(const fs::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return false;
    const bool ok = ::fsync(fd) == 0;
    return ::close(fd) == 0 && ok;
}

// One column of the step: a 1-D dataset of `total` values, of which this rank
// writes [first, first + count) from `values`, collectively.
void writeColumn(const Writers& ranks, hid_t group, hid_t transfer, const char* name,
                 hid_t fileType, hid_t memoryType, const void* values, std::uint64_t first,
                 std::uint64_t count, std::uint64_t total) {
    const std::string what = std::string("cannot write dataset '") + name + "'";
    const hsize_t dims = total, offset = first, n = count;
    const H5Handle fileSpace(H5Screate_simple(1, &dims, nullptr), H5Sclose);
    const H5Handle memorySpace(H5Screate_simple(1, &n, nullptr), H5Sclose);
    bool ok = fileSpace.valid() && memorySpace.valid();
    if (ok && count > 0)
        ok = H5Sselect_hyperslab(fileSpace.get(), H5S_SELECT_SET, &offset, nullptr, &n, nullptr) >=
             0;
    else if (ok)  // no particles here: an empty selection, still part of the collective write
        ok = H5Sselect_none(fileSpace.get()) >= 0 && H5Sselect_none(memorySpace.get()) >= 0;
    ranks.agreeHdf5(ok, what);
    H5Handle dataset(
        H5Dcreate2(group, name, fileType, fileSpace.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
        H5Dclose);
    ranks.agreeHdf5(dataset.valid(), what);
    // HDF5 wants a buffer even for an empty selection.
    static const std::int64_t kNothing = 0;
    ranks.agreeHdf5(H5Dwrite(dataset.get(), memoryType, memorySpace.get(), fileSpace.get(),
                             transfer, count > 0 ? values : &kNothing) >= 0,
                    what);
    ranks.agreeHdf5(dataset.close(), what);
}

// A scalar attribute of `object`, written collectively (every rank the same value).
void writeAttribute(const Writers& ranks, hid_t object, const char* name, hid_t fileType,
                    hid_t memoryType, const void* value) {
    const H5Handle scalar(H5Screate(H5S_SCALAR), H5Sclose);
    ranks.agreeHdf5(scalar.valid(), std::string("cannot write attribute ") + name);
    const H5Handle attribute(
        H5Acreate2(object, name, fileType, scalar.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
    ranks.agreeHdf5(attribute.valid() && H5Awrite(attribute.get(), memoryType, value) >= 0,
                    std::string("cannot write attribute ") + name);
}

void writeStep(const Writers& ranks, const fs::path& temporary, int frame, double time,
               const ParticleStore& part, const std::vector<std::int64_t>& ids, std::uint64_t first,
               std::uint64_t total) {
    const H5Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    const H5Handle transfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
    bool ok = access.valid() && transfer.valid();
    // MPI-IO with collective transfers: every rank writes its range of each
    // dataset in one MPI_File_write_at_all (ROMIO/OMPIO aggregate them).
    if (ok && ranks.mpi())
        ok = H5Pset_fapl_mpio(access.get(), ranks.comm(), MPI_INFO_NULL) >= 0 &&
             H5Pset_dxpl_mpio(transfer.get(), H5FD_MPIO_COLLECTIVE) >= 0;
    ranks.agreeHdf5(ok, "cannot set up HDF5");

    H5Handle file(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get()), H5Fclose);
    ranks.agreeHdf5(file.valid(), "cannot create file (is the directory writable?)");
    {
        // H5Part numbers a file's steps Step#0, Step#1, ...: ParaView's
        // H5Part reader opens the step groups by index from Step#0, and a
        // file holding only Step#12 shows nothing. The frame's number is the
        // group's attribute Frame instead.
        const std::string stepName = "Step#0";
        H5Handle group(
            H5Gcreate2(file.get(), stepName.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
            H5Gclose);
        ranks.agreeHdf5(group.valid(), "cannot create group '" + stepName + "'");
        // ParaView takes a step's time from its TimeValue attribute when that
        // is one native double (otherwise it numbers the steps 0, 1, ...).
        writeAttribute(ranks, group.get(), "TimeValue", H5T_NATIVE_DOUBLE, H5T_NATIVE_DOUBLE,
                       &time);
        writeAttribute(ranks, group.get(), "Frame", H5T_STD_I32LE, H5T_NATIVE_INT, &frame);
        const std::uint64_t count = part.size();
        const struct {
            const char* name;
            const float* values;
        } floats[] = {{"x", part.position.x.data()},   {"y", part.position.y.data()},
                      {"z", part.position.z.data()},   {"vx", part.velocity.x.data()},
                      {"vy", part.velocity.y.data()},  {"vz", part.velocity.z.data()},
                      {"density", part.density.data()}};
        for (const auto& column : floats)
            writeColumn(ranks, group.get(), transfer.get(), column.name, H5T_IEEE_F32LE,
                        H5T_NATIVE_FLOAT, column.values, first, count, total);
        writeColumn(ranks, group.get(), transfer.get(), "id", H5T_STD_I64LE, H5T_NATIVE_INT64,
                    ids.data(), first, count, total);
        ranks.agreeHdf5(group.close(), "cannot close group '" + stepName + "'");
    }
    // With MPI-IO a global flush is MPI_File_sync on every rank: the data
    // reach the file system before rank 0 renames the file.
    ranks.agreeHdf5(H5Fflush(file.get(), H5F_SCOPE_GLOBAL) >= 0, "cannot flush file");
    ranks.agreeHdf5(file.close(), "cannot close file (disk full?)");
}

// Writes `file` whole: write(temporary) fills a temporary file beside it
// (HDF5 handles all closed when it returns), then rank 0 syncs it and renames
// it over `file`. Throws on every rank alike; no temporary file is left.
template <class Write>
void writeWhole(const Writers& ranks, const fs::path& file, Write&& write) {
    const QuietHdf5 quiet;
    const fs::path temporary = temporaryName(ranks, file);
    const auto removeTemporary = [&] {
        std::error_code ignored;
        if (ranks.rank() == 0) fs::remove(temporary, ignored);
    };
    try {
        write(temporary);
    } catch (const IoError&) {
        // Every rank agreed on every outcome, so all are here together,
        // their HDF5 handles closed.
        removeTemporary();
        throw;
    }
    // Every rank has closed the file (the agreement on H5Fclose is the
    // barrier): rank 0 publishes it and tells the others how that went.
    std::string failure;
    if (ranks.rank() == 0) {
        std::error_code ec;
        if (!syncFile(temporary)) {
            failure = "write failed when syncing to disk (disk full?)";
        } else {
            fs::rename(temporary, file, ec);
            if (ec) failure = "cannot rename temporary file into place: " + ec.message();
        }
        if (!failure.empty()) removeTemporary();
    }
    failure = ranks.broadcast(failure, 0);
    if (!failure.empty()) throw IoError(file.string() + ": " + failure);
}

}  // namespace

bool h5partBuilt() {
    return true;
}

H5PartComm H5PartComm::run() {
    if (!distributed::active()) return thisProcess();
    return mpi(MPI_Comm_c2f(MPI_COMM_WORLD));
}

void writeH5PartFile(const fs::path& file, int frame, double time, const ParticleStore& part,
                     std::uint64_t first, std::uint64_t total, H5PartComm comm) {
    const Writers ranks(comm, file);
    checkParts(ranks, file, first, part.size(), total);
    // The ids as the file's int64 (converted here rather than by HDF5: a
    // conversion in H5Dwrite turns a collective transfer into independent ones).
    std::vector<std::int64_t> ids;
    bool allocated = true;
    try {
        ids.assign(part.id.begin(), part.id.end());
    } catch (const std::bad_alloc&) {
        allocated = false;
    }
    ranks.agree(allocated, "cannot write", "out of memory");
    ranks.agree(std::none_of(ids.begin(), ids.end(), [](std::int64_t id) { return id < 0; }),
                "cannot write", "a particle id past 2^63 - 1, the file's int64");

    writeWhole(ranks, file, [&](const fs::path& temporary) {
        writeStep(ranks, temporary, frame, time, part, ids, first, total);
    });
}

void writeH5PartIndex(const fs::path& file, std::span<const fs::path> frames) {
    const Writers self(H5PartComm::thisProcess(), file);
    writeWhole(self, file, [&](const fs::path& temporary) {
        H5Handle h5(H5Fcreate(temporary.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                    H5Fclose);
        self.agreeHdf5(h5.valid(), "cannot create file (is the directory writable?)");
        // An external link is a name: HDF5 resolves a relative one against
        // the index's own directory when ParaView follows it.
        for (std::size_t k = 0; k < frames.size(); ++k) {
            const std::string step = "Step#" + std::to_string(k);
            self.agreeHdf5(H5Lcreate_external(frames[k].c_str(), "/Step#0", h5.get(), step.c_str(),
                                              H5P_DEFAULT, H5P_DEFAULT) >= 0,
                           "cannot link " + step + " to " + frames[k].string());
        }
        self.agreeHdf5(h5.close(), "cannot close file (disk full?)");
    });
}

namespace {

// A 1-D dataset of the step read whole as `memoryType`; false when absent.
template <class T>
bool readColumn(hid_t group, const fs::path& file, const char* name, hid_t memoryType,
                std::size_t& count, std::vector<T>& out) {
    const auto fail = [&](const std::string& what) {
        throw IoError(file.string() + ": dataset '" + name + "': " + what);
    };
    const htri_t exists = H5Lexists(group, name, H5P_DEFAULT);
    if (exists < 0) fail(hdf5Reason());
    if (exists == 0) return false;
    const H5Handle dataset(H5Dopen2(group, name, H5P_DEFAULT), H5Dclose);
    if (!dataset.valid()) fail("cannot open (" + hdf5Reason() + ")");
    const H5Handle space(H5Dget_space(dataset.get()), H5Sclose);
    hsize_t dims = 0;
    if (!space.valid() || H5Sget_simple_extent_ndims(space.get()) != 1 ||
        H5Sget_simple_extent_dims(space.get(), &dims, nullptr) != 1)
        fail("not a 1-D dataset");
    if (count == std::numeric_limits<std::size_t>::max()) {
        // The first column sets the particle count; refuse counts the file
        // cannot hold before allocating for them.
        const H5Handle type(H5Dget_type(dataset.get()), H5Tclose);
        const std::size_t bytes = type.valid() ? H5Tget_size(type.get()) : 0;
        if (bytes == 0 || dims > H5Dget_storage_size(dataset.get()) / bytes)
            fail("holds fewer values than its size says");
        count = std::size_t(dims);
    } else if (dims != count) {
        fail(std::to_string(dims) + " values, not " + std::to_string(count) + " as x");
    }
    out.resize(count);
    if (count > 0 &&
        H5Dread(dataset.get(), memoryType, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
        fail("cannot read (" + hdf5Reason() + ")");
    return true;
}

// A scalar attribute of `object` as `memoryType`; left empty when absent.
template <class T>
void readAttribute(hid_t object, const fs::path& file, const char* name, hid_t memoryType,
                   std::optional<T>& out) {
    if (H5Aexists(object, name) <= 0) return;
    const H5Handle attribute(H5Aopen(object, name, H5P_DEFAULT), H5Aclose);
    T value{};
    if (!attribute.valid() || H5Aread(attribute.get(), memoryType, &value) < 0)
        throw IoError(file.string() + ": cannot read attribute " + name + " (" + hdf5Reason() +
                      ")");
    out = value;
}

// The file's step groups by number ("Step#12" -> 12), lowest first.
std::vector<std::pair<long long, std::string>> stepGroups(hid_t file, const fs::path& path) {
    using Steps = std::vector<std::pair<long long, std::string>>;
    Steps steps;
    const auto visit = [](hid_t, const char* name, const H5L_info_t*, void* out) -> herr_t {
        constexpr std::string_view kPrefix = "Step#";
        const std::string_view text(name);
        if (!text.starts_with(kPrefix)) return 0;
        long long step = 0;
        const char* begin = text.data() + kPrefix.size();
        const char* end = text.data() + text.size();
        const auto [stop, error] = std::from_chars(begin, end, step);
        if (error == std::errc() && stop == end && begin != end)
            static_cast<Steps*>(out)->emplace_back(step, std::string(text));
        return 0;
    };
    if (H5Literate(file, H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, visit, &steps) < 0)
        throw IoError(path.string() + ": cannot list the file's groups (" + hdf5Reason() + ")");
    std::sort(steps.begin(), steps.end());
    return steps;
}

}  // namespace

H5PartFrame readH5PartFile(const fs::path& file) {
    const QuietHdf5 quiet;
    const H5Handle h5(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!h5.valid())
        throw IoError(file.string() + ": cannot open H5Part file (" + hdf5Reason() + ")");
    const auto steps = stepGroups(h5.get(), file);
    if (steps.empty()) throw IoError(file.string() + ": no Step#<n> group (not an H5Part file)");
    const std::string& name = steps.front().second;
    const H5Handle group(H5Gopen2(h5.get(), name.c_str(), H5P_DEFAULT), H5Gclose);
    if (!group.valid())
        throw IoError(file.string() + ": cannot open group '" + name + "' (" + hdf5Reason() + ")");

    H5PartFrame frame;
    readAttribute(group.get(), file, "TimeValue", H5T_NATIVE_DOUBLE, frame.time);
    readAttribute(group.get(), file, "Frame", H5T_NATIVE_INT, frame.frame);

    std::size_t count = std::numeric_limits<std::size_t>::max();
    std::array<std::vector<float>, 3> position, velocity;
    const char* positionNames[] = {"x", "y", "z"};
    const char* velocityNames[] = {"vx", "vy", "vz"};
    for (int c = 0; c < 3; ++c)
        if (!readColumn(group.get(), file, positionNames[c], H5T_NATIVE_FLOAT, count, position[c]))
            throw IoError(file.string() + ": group '" + name + "' has no dataset '" +
                          positionNames[c] + "'");
    int velocityColumns = 0;
    for (int c = 0; c < 3; ++c)
        velocityColumns +=
            readColumn(group.get(), file, velocityNames[c], H5T_NATIVE_FLOAT, count, velocity[c]);
    std::vector<std::int64_t> ids;
    const bool hasIds = readColumn(group.get(), file, "id", H5T_NATIVE_INT64, count, ids);
    readColumn(group.get(), file, "density", H5T_NATIVE_FLOAT, count, frame.particles.density);

    ParticleFrame& p = frame.particles;
    p.position.resize(count);
    for (std::size_t i = 0; i < count; ++i)
        p.position[i] = {position[0][i], position[1][i], position[2][i]};
    if (velocityColumns == 3) {
        p.velocity.resize(count);
        for (std::size_t i = 0; i < count; ++i)
            p.velocity[i] = {velocity[0][i], velocity[1][i], velocity[2][i]};
    }
    if (hasIds) {
        p.id.resize(count);
        for (std::size_t i = 0; i < count; ++i) {
            if (ids[i] < 0)
                throw IoError(file.string() + ": negative particle id " + std::to_string(ids[i]));
            p.id[i] = std::uint64_t(ids[i]);
        }
    }
    return frame;
}

}  // namespace pbf
