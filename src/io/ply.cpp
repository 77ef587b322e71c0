#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "io/particle_ply.hpp"
#include "pbf/io/io.hpp"

namespace pbf {
namespace {

static_assert(std::endian::native == std::endian::little,
              "binary PLY output assumes a little-endian host");

std::size_t propertyBytes(std::string_view type) {
    if (type == "float" || type == "uint") return 4;
    if (type == "uchar") return 1;
    throw std::logic_error("PLY property type '" + std::string(type) + "' is not written by pbf");
}

[[noreturn]] void fail(const std::string& name, const std::string& message) {
    throw IoError(name + ": " + message);
}

}  // namespace

std::string detail::plyHeader(std::string_view comment, std::span<const PlyProperty> properties,
                              std::uint64_t count) {
    std::string header = "ply\nformat binary_little_endian 1.0\ncomment " + std::string(comment) +
                         "\nelement vertex " + std::to_string(count) + "\n";
    for (const PlyProperty& p : properties)
        header += "property " + std::string(p.type) + " " + std::string(p.name) + "\n";
    return header + "end_header\n";
}

void writeVertexPly(const std::filesystem::path& path, std::string_view comment,
                    std::span<const PlyProperty> properties, std::size_t count,
                    const std::function<void(std::size_t k, char* record)>& fill) {
    std::size_t stride = 0;
    for (const PlyProperty& p : properties) stride += propertyBytes(p.type);
    writeFileAtomically(path, [&](std::ostream& out) {
        out << detail::plyHeader(comment, properties, count);
        // Records written in chunks of up to 64k vertices.
        constexpr std::size_t kChunk = 65536;
        std::vector<char> buffer(std::min(count, kChunk) * stride);
        for (std::size_t first = 0; first < count; first += kChunk) {
            const std::size_t n = std::min(kChunk, count - first);
            for (std::size_t k = 0; k < n; ++k) fill(first + k, buffer.data() + k * stride);
            out.write(buffer.data(), static_cast<std::streamsize>(n * stride));
        }
    });
}

std::uint32_t plyId(std::uint64_t id, const std::filesystem::path& path) {
    if (id > std::numeric_limits<std::uint32_t>::max())
        fail(path.string(),
             "particle id " + std::to_string(id) +
                 " does not fit the PLY files' 32-bit id: this run created more than 2^32 "
                 "particles; write its frames as VTK (output.vtk) or USD (output.usd), which keep "
                 "64-bit ids, and set output.particles to false");
    return static_cast<std::uint32_t>(id);
}

detail::ParticlePlyRecord detail::particlePlyRecord(const ParticleStore& p, std::size_t i,
                                                    const std::filesystem::path& path) {
    return {{p.position.x[i], p.position.y[i], p.position.z[i], p.velocity.x[i], p.velocity.y[i],
             p.velocity.z[i], p.density[i]},
            plyId(p.id[i], path)};
}

void writeParticlesPly(const std::filesystem::path& path, const ParticleStore& p) {
    const std::vector<std::uint32_t> order = p.orderById();
    writeVertexPly(path, detail::kParticlePlyComment, detail::kParticlePlyProperties, order.size(),
                   [&](std::size_t k, char* record) {
                       const detail::ParticlePlyRecord r =
                           detail::particlePlyRecord(p, order[k], path);
                       std::memcpy(record, &r, sizeof r);
                   });
}

ParticleFrame readParticlesPly(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path.string(), "cannot open PLY file");
    return readParticlesPly(in, path.string());
}

ParticleFrame readParticlesPly(std::istream& in, const std::string& path) {
    std::string line;
    if (!std::getline(in, line) || line != "ply") fail(path, "not a PLY file (no 'ply' magic)");

    struct Property {
        std::string name;
        std::size_t size;
        bool isFloat;
    };
    std::vector<Property> properties;
    std::size_t count = 0;
    bool inVertex = false, sawFormat = false;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string word;
        words >> word;
        if (word == "end_header") break;
        if (word == "format") {
            std::string format;
            words >> format;
            if (format != "binary_little_endian")
                fail(path, "only binary_little_endian PLY is supported");
            sawFormat = true;
        } else if (word == "element") {
            std::string name;
            words >> name;
            inVertex = name == "vertex";
            if (inVertex && !(words >> count)) fail(path, "bad vertex count");
            if (!inVertex) fail(path, "unsupported element '" + name + "' (only vertex)");
        } else if (word == "property" && inVertex) {
            std::string type, name;
            words >> type >> name;
            if (type == "float" || type == "float32")
                properties.push_back({name, 4, true});
            else if (type == "uint" || type == "uint32" || type == "int" || type == "int32")
                properties.push_back({name, 4, false});
            else
                fail(path, "unsupported property type '" + type + "'");
        }
    }
    if (!in || !sawFormat) fail(path, "truncated or malformed PLY header");
    const std::size_t stride = properties.size() * 4;
    // Refuse counts the file cannot hold before allocating for them.
    const auto headerEnd = in.tellg();
    in.seekg(0, std::ios::end);
    const auto bytes = static_cast<std::size_t>(in.tellg() - headerEnd);
    in.seekg(headerEnd);
    if (stride == 0 || count > bytes / stride)
        fail(path, "file is shorter than its vertex count says");

    auto column = [&](const char* name) -> int {
        for (std::size_t k = 0; k < properties.size(); ++k)
            if (properties[k].name == name) return static_cast<int>(k);
        return -1;
    };
    const int ix = column("x"), iy = column("y"), iz = column("z");
    if (ix < 0 || iy < 0 || iz < 0) fail(path, "vertex element lacks x, y, z");
    const int ivx = column("vx"), ivy = column("vy"), ivz = column("vz"), idens = column("density"),
              iid = column("id");

    ParticleFrame frame;
    frame.position.resize(count);
    if (ivx >= 0 && ivy >= 0 && ivz >= 0) frame.velocity.resize(count);
    if (idens >= 0) frame.density.resize(count);
    if (iid >= 0) frame.id.resize(count);
    std::vector<char> row(stride);
    auto floatAt = [&](int k) {
        float v;
        std::memcpy(&v, row.data() + 4 * k, 4);
        return v;
    };
    for (std::size_t i = 0; i < count; ++i) {
        if (!in.read(row.data(), static_cast<std::streamsize>(stride)))
            fail(path, "truncated vertex data");
        frame.position[i] = {floatAt(ix), floatAt(iy), floatAt(iz)};
        if (!frame.velocity.empty()) frame.velocity[i] = {floatAt(ivx), floatAt(ivy), floatAt(ivz)};
        if (!frame.density.empty()) frame.density[i] = floatAt(idens);
        if (!frame.id.empty()) {
            std::uint32_t id;
            std::memcpy(&id, row.data() + 4 * iid, 4);
            frame.id[i] = id;
        }
    }
    return frame;
}

}  // namespace pbf
