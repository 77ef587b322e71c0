// VTK XML writers (include/pbf/io/vtk.hpp): the XML header names every array
// and its offset into one raw <AppendedData> block, where each array is its
// UInt64 byte count followed by its little-endian bytes. Arrays are produced
// in chunks straight into the stream, so a frame never exists twice in memory.
#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "pbf/io/io.hpp"
#include "pbf/io/vtk.hpp"

namespace pbf::vtk {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the VTK files are written as LittleEndian from memory");

enum class Scalar { Float32, UInt8, UInt32, Int32, Int64, UInt64 };

const char* typeName(Scalar type) {
    switch (type) {
        case Scalar::Float32:
            return "Float32";
        case Scalar::UInt8:
            return "UInt8";
        case Scalar::UInt32:
            return "UInt32";
        case Scalar::Int32:
            return "Int32";
        case Scalar::Int64:
            return "Int64";
        case Scalar::UInt64:
            return "UInt64";
    }
    return "";
}

std::size_t typeSize(Scalar type) {
    switch (type) {
        case Scalar::UInt8:
            return 1;
        case Scalar::Float32:
        case Scalar::UInt32:
        case Scalar::Int32:
            return 4;
        case Scalar::Int64:
        case Scalar::UInt64:
            return 8;
    }
    return 0;
}

// One data array of the appended block.
struct Array {
    std::string name;
    Scalar type = Scalar::Float32;
    int components = 1;
    std::size_t tuples = 0;
    // Writes tuples [first, first + count) to `out` (count * components values).
    std::function<void(std::size_t first, std::size_t count, std::byte* out)> fill;

    std::uint64_t bytes() const { return std::uint64_t{tuples} * components * typeSize(type); }
};

// The arrays of one file in appended order, with their offsets.
class Appended {
  public:
    // Returns the <DataArray> tag of `array` (added to the block).
    std::string add(Array array) {
        std::string tag =
            fmt::format(R"(<DataArray type="{}" Name="{}")", typeName(array.type), array.name);
        if (array.components != 1)
            tag += fmt::format(R"( NumberOfComponents="{}")", array.components);
        tag += fmt::format(R"( format="appended" offset="{}"/>)", offset_);
        offset_ += sizeof(std::uint64_t) + array.bytes();
        arrays_.push_back(std::move(array));
        return tag;
    }

    void write(std::ostream& out) const {
        out << "  <AppendedData encoding=\"raw\">\n   _";
        std::vector<std::byte> buffer;
        for (const Array& a : arrays_) {
            const std::uint64_t bytes = a.bytes();
            out.write(reinterpret_cast<const char*>(&bytes), sizeof bytes);
            const std::size_t tupleBytes = a.components * typeSize(a.type);
            constexpr std::size_t kChunk = 65536;  // tuples per write
            buffer.resize(std::min(a.tuples, kChunk) * tupleBytes);
            for (std::size_t first = 0; first < a.tuples; first += kChunk) {
                const std::size_t count = std::min(kChunk, a.tuples - first);
                a.fill(first, count, buffer.data());
                out.write(reinterpret_cast<const char*>(buffer.data()),
                          static_cast<std::streamsize>(count * tupleBytes));
            }
        }
        out << "\n  </AppendedData>\n</VTKFile>\n";
    }

  private:
    std::uint64_t offset_ = 0;
    std::vector<Array> arrays_;
};

template <typename T>
void store(std::byte* out, std::size_t index, T value) {
    std::memcpy(out + index * sizeof(T), &value, sizeof(T));
}

// x, y, z of the particles `order[first, first + count)` interleaved.
Array vectorArray(std::string name, const Float3Array& v, const std::vector<std::uint32_t>& order) {
    return {std::move(name), Scalar::Float32, 3, order.size(),
            [&v, &order](std::size_t first, std::size_t count, std::byte* out) {
                for (std::size_t k = 0; k < count; ++k) {
                    const std::uint32_t i = order[first + k];
                    store(out, 3 * k, v.x[i]);
                    store(out, 3 * k + 1, v.y[i]);
                    store(out, 3 * k + 2, v.z[i]);
                }
            }};
}

// Tuples of `components` consecutive values of `values`.
template <typename T>
Array contiguousArray(std::string name, Scalar type, int components, std::span<const T> values) {
    const std::size_t width = static_cast<std::size_t>(components);
    return {std::move(name), type, components, values.size() / width,
            [values, width](std::size_t first, std::size_t count, std::byte* out) {
                std::memcpy(out, values.data() + first * width, count * width * sizeof(T));
            }};
}

// Cell connectivity and offsets hold point indices: Int32 while they fit
// (half the bytes), Int64 beyond.
Scalar indexType(std::uint64_t largest) {
    return largest <= 0x7fffffffu ? Scalar::Int32 : Scalar::Int64;
}

// Index array whose value at position k is f(k).
template <typename F>
Array indexArray(std::string name, Scalar type, std::size_t count, F f) {
    return {std::move(name), type, 1, count,
            [type, f](std::size_t first, std::size_t n, std::byte* out) {
                for (std::size_t k = 0; k < n; ++k) {
                    const std::uint64_t value = f(first + k);
                    if (type == Scalar::Int32)
                        store(out, k, static_cast<std::int32_t>(value));
                    else
                        store(out, k, static_cast<std::int64_t>(value));
                }
            }};
}

std::string header(const char* type) {
    return fmt::format(
        "<?xml version=\"1.0\"?>\n<!-- written by pbf -->\n"
        "<VTKFile type=\"{}\" version=\"1.0\" byte_order=\"LittleEndian\" "
        "header_type=\"UInt64\">\n",
        type);
}

// ParaView takes the time of a file opened on its own (or as a numbered
// series) from this field array.
std::string timeField(double time) {
    return fmt::format(
        "    <FieldData>\n      <DataArray type=\"Float64\" Name=\"TimeValue\" "
        "NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n    </FieldData>\n",
        time);
}

}  // namespace

void writeParticlesVtu(const std::filesystem::path& path, const ParticleStore& p, double time) {
    const std::vector<std::uint32_t> order = p.orderById();
    const std::size_t n = order.size();
    Appended block;
    const std::string velocity = block.add(vectorArray("velocity", p.velocity, order));
    const std::string density =
        block.add({"density", Scalar::Float32, 1, n,
                   [&](std::size_t first, std::size_t count, std::byte* out) {
                       for (std::size_t k = 0; k < count; ++k)
                           store(out, k, p.density[order[first + k]]);
                   }});
    const std::string id = block.add(
        {"id", Scalar::UInt64, 1, n, [&](std::size_t first, std::size_t count, std::byte* out) {
             for (std::size_t k = 0; k < count; ++k) store(out, k, p.id[order[first + k]]);
         }});
    const std::string points = block.add(vectorArray("Points", p.position, order));
    // One vertex cell per particle: cell k holds point k.
    const Scalar index = indexType(n);
    const std::string connectivity =
        block.add(indexArray("connectivity", index, n, [](std::size_t k) { return k; }));
    const std::string offsets =
        block.add(indexArray("offsets", index, n, [](std::size_t k) { return k + 1; }));
    const std::string types = block.add(
        {"types", Scalar::UInt8, 1, n, [](std::size_t, std::size_t count, std::byte* out) {
             std::memset(out, 1, count);  // VTK_VERTEX
         }});
    writeFileAtomically(path, [&](std::ostream& out) {
        out << header("UnstructuredGrid") << "  <UnstructuredGrid>\n"
            << timeField(time)
            << fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n)
            << "      <PointData Scalars=\"density\" Vectors=\"velocity\">\n"
            << "        " << velocity << "\n        " << density << "\n        " << id << "\n"
            << "      </PointData>\n      <Points>\n        " << points << "\n      </Points>\n"
            << "      <Cells>\n        " << connectivity << "\n        " << offsets << "\n        "
            << types << "\n      </Cells>\n"
            << "    </Piece>\n  </UnstructuredGrid>\n";
        block.write(out);
    });
}

void writeTrianglesVtp(const std::filesystem::path& path, std::span<const Vec3> vertices,
                       std::span<const Vec3> normals,
                       std::span<const std::array<std::uint32_t, 3>> triangles, double time) {
    if (!normals.empty() && normals.size() != vertices.size())
        throw IoError(path.string() + ": " + std::to_string(normals.size()) + " normals for " +
                      std::to_string(vertices.size()) + " vertices");
    static_assert(sizeof(Vec3) == 12 && sizeof(std::array<std::uint32_t, 3>) == 12);
    const std::span<const float> xyz(reinterpret_cast<const float*>(vertices.data()),
                                     3 * vertices.size());
    const std::size_t t = triangles.size();
    Appended block;
    std::string normalTag;
    if (!normals.empty())
        normalTag = block.add(
            contiguousArray("Normals", Scalar::Float32, 3,
                            std::span<const float>(reinterpret_cast<const float*>(normals.data()),
                                                   3 * normals.size())));
    const std::string points = block.add(contiguousArray("Points", Scalar::Float32, 3, xyz));
    const Scalar index = indexType(3 * std::uint64_t{t});
    const std::string connectivity =
        block.add(indexArray("connectivity", index, 3 * t,
                             [triangles](std::size_t k) { return triangles[k / 3][k % 3]; }));
    const std::string offsets =
        block.add(indexArray("offsets", index, t, [](std::size_t k) { return 3 * (k + 1); }));
    writeFileAtomically(path, [&](std::ostream& out) {
        out << header("PolyData") << "  <PolyData>\n"
            << timeField(time)
            << fmt::format(
                   "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" "
                   "NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
                   vertices.size(), t);
        if (!normalTag.empty())
            out << "      <PointData Normals=\"Normals\">\n        " << normalTag
                << "\n      </PointData>\n";
        out << "      <Points>\n        " << points << "\n      </Points>\n"
            << "      <Polys>\n        " << connectivity << "\n        " << offsets
            << "\n      </Polys>\n    </Piece>\n  </PolyData>\n";
        block.write(out);
    });
}

}  // namespace pbf::vtk
