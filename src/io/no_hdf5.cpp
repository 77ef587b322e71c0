// H5Part files in a build without parallel HDF5 (PBF_HDF5 off): every
// function says what to install.
#include <string>

#include "pbf/io/h5part.hpp"

namespace pbf {
namespace {

[[noreturn]] void refuse(const std::filesystem::path& file) {
    throw IoError(file.string() +
                  ": pbf was built without parallel HDF5; install libhdf5-openmpi-dev and "
                  "reconfigure");
}

}  // namespace

bool h5partBuilt() {
    return false;
}

H5PartComm H5PartComm::run() {
    return thisProcess();
}

void writeH5PartFile(const std::filesystem::path& file, int, double, const ParticleStore&,
                     std::uint64_t, std::uint64_t, H5PartComm) {
    refuse(file);
}

void writeH5PartIndex(const std::filesystem::path& file, std::span<const std::filesystem::path>) {
    refuse(file);
}

H5PartFrame readH5PartFile(const std::filesystem::path& file) {
    refuse(file);
}

}  // namespace pbf
