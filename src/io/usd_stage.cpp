// USD text layers of a run (include/pbf/io/usd.hpp): the root layer with the
// time metadata and value clips, and one layer per frame.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>

#include "pbf/io/io.hpp"
#include "pbf/io/usd.hpp"

namespace pbf::usd {
namespace {

namespace fs = std::filesystem;

// Text for one layer, formatted into a buffer that is handed to the stream
// a megabyte at a time (a 1M-particle frame is about 100 MB of text).
class Text {
  public:
    explicit Text(std::ostream& out) : out_(out) {}
    ~Text() { flush(); }
    Text(const Text&) = delete;
    Text& operator=(const Text&) = delete;

    template <typename... Args>
    void put(fmt::format_string<Args...> format, Args&&... args) {
        fmt::format_to(std::back_inserter(buffer_), format, std::forward<Args>(args)...);
        if (buffer_.size() > (1u << 20)) flush();
    }
    void flush() {
        out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
        buffer_.clear();
    }

  private:
    std::ostream& out_;
    fmt::memory_buffer buffer_;
};

// Floats in their shortest form that reads back to the same float (fmt's
// default for float: "0.1", not "0.100000001"); doubles likewise.
void putVec(Text& t, const Vec3& v) {
    t.put("({}, {}, {})", v.x, v.y, v.z);
}

template <typename T, typename Put>
void putArray(Text& t, std::span<const T> values, Put put) {
    t.put("[");
    for (std::size_t i = 0; i < values.size(); ++i) {
        if (i > 0) t.put(", ");
        put(values[i]);
    }
    t.put("]");
}

void putVecArray(Text& t, std::span<const Vec3> values) {
    putArray(t, values, [&](const Vec3& v) { putVec(t, v); });
}

template <typename T>
void putNumberArray(Text& t, std::span<const T> values) {
    putArray(t, values, [&](const T& v) { t.put("{}", v); });
}

// `type name.timeSamples = { frame: value, }` with the value put by `value`.
template <typename Put>
void putSample(Text& t, const char* declaration, int frame, Put value) {
    t.put("    {}.timeSamples = {{\n        {}: ", declaration, frame);
    value();
    t.put(",\n    }}\n");
}

// Bounds of the points, grown by `pad` (a point's radius).
std::array<Vec3, 2> bounds(std::span<const Vec3> points, float pad) {
    if (points.empty()) return {Vec3{}, Vec3{}};
    Vec3 lo = points[0], hi = points[0];
    for (const Vec3& p : points) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    const Vec3 d{pad, pad, pad};
    return {lo - d, hi + d};
}

void putExtent(Text& t, const std::array<Vec3, 2>& box) {
    t.put("[");
    putVec(t, box[0]);
    t.put(", ");
    putVec(t, box[1]);
    t.put("]");
}

// The triangles as USD's face counts and indices.
void putFaceCounts(Text& t, std::size_t triangles) {
    t.put("[");
    for (std::size_t i = 0; i < triangles; ++i) t.put("{}", i > 0 ? ", 3" : "3");
    t.put("]");
}
void putFaceIndices(Text& t, std::span<const std::array<std::uint32_t, 3>> triangles) {
    putArray(t, triangles,
             [&](const std::array<std::uint32_t, 3>& f) { t.put("{}, {}, {}", f[0], f[1], f[2]); });
}

// A string as a USD string literal.
std::string quoted(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') out += '\\';
        out += (c == '\n') ? ' ' : c;
    }
    return out + "\"";
}

// Attribute metadata that clip layers cannot carry (only values come from
// clips): declared in the root layer.
const char* declarationMetadata(const std::string& declaration) {
    if (declaration.find("primvars:") != std::string::npos || declaration.ends_with(" widths") ||
        declaration.ends_with(" normals"))
        return " (\n            interpolation = \"vertex\"\n        )";
    return "";
}

void putStaticMesh(Text& t, const StaticMesh& m, const std::string& indent) {
    t.put("{}def Mesh \"{}\"\n{}{{\n", indent, m.name, indent);
    const std::string in = indent + "    ";
    t.put("{}float3[] extent = ", in);
    putExtent(t, bounds(m.vertices, 0.0f));
    t.put("\n{}int[] faceVertexCounts = ", in);
    putFaceCounts(t, m.triangles.size());
    t.put("\n{}int[] faceVertexIndices = ", in);
    putFaceIndices(t, std::span(m.triangles));
    if (!m.normals.empty()) {
        t.put("\n{}normal3f[] normals = ", in);
        putVecArray(t, m.normals);
        t.put(" (\n{}    interpolation = \"vertex\"\n{})", in, in);
    }
    t.put("\n{}point3f[] points = ", in);
    putVecArray(t, m.vertices);
    t.put("\n{}uniform token subdivisionScheme = \"none\"\n", in);
    if (!m.pose.identity()) {
        const Quat& q = m.pose.orientation;
        t.put("{}float3 xformOp:translate = ", in);
        putVec(t, m.pose.position);
        t.put("\n{}quatf xformOp:orient = ({}, {}, {}, {})\n", in, q.w, q.x, q.y, q.z);
        t.put("{}uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:orient\"]\n", in);
    }
    t.put("{}}}\n", indent);
}

void putBody(Text& t, const BodyTrack& b) {
    t.put("        def Xform \"{}\"\n        {{\n", b.name);
    t.put("            double3 xformOp:translate.timeSamples = {{\n");
    for (std::size_t k = 0; k < b.frames.size(); ++k)
        t.put("                {}: ({}, {}, {}),\n", b.frames[k], b.position[k][0],
              b.position[k][1], b.position[k][2]);
    t.put("            }}\n            quatd xformOp:orient.timeSamples = {{\n");
    for (std::size_t k = 0; k < b.frames.size(); ++k)
        t.put("                {}: ({}, {}, {}, {}),\n", b.frames[k], b.orientation[k][0],
              b.orientation[k][1], b.orientation[k][2], b.orientation[k][3]);
    t.put("            }}\n");
    t.put(
        "            uniform token[] xformOpOrder = [\"xformOp:translate\", "
        "\"xformOp:orient\"]\n");
    if (b.shape) {
        t.put("\n");
        putStaticMesh(t, *b.shape, "            ");
    }
    t.put("        }}\n");
}

// A perspective camera looking from `position` at `target` with +y up
// (USD cameras look down their -z axis). Focal length and apertures are
// in tenths of a unit as USD defines them; only their ratio (the field of
// view) matters here.
void putCamera(Text& t, const Camera& c) {
    const auto unit = [](const Vec3& v) { return v * (1.0f / length(v)); };
    const Vec3 back = unit(c.position - c.target);
    const Vec3 right = unit(cross(Vec3{0, 1, 0}, back));
    const Vec3 up = cross(back, right);
    const double vertical = 24.0;
    const double focal = 0.5 * vertical / std::tan(0.5 * double(c.fovY) * std::numbers::pi / 180.0);
    t.put("    def Camera \"camera\"\n    {{\n");
    t.put("        float2 clippingRange = (0.01, 1000)\n");
    t.put("        float focalLength = {}\n", float(focal));
    t.put("        float horizontalAperture = {}\n", float(vertical * c.aspect));
    t.put("        token projection = \"perspective\"\n");
    t.put("        float verticalAperture = {}\n", float(vertical));
    t.put(
        "        matrix4d xformOp:transform = ( ({}, {}, {}, 0), ({}, {}, {}, 0), ({}, {}, {}, 0), "
        "({}, {}, {}, 1) )\n",
        right.x, right.y, right.z, up.x, up.y, up.z, back.x, back.y, back.z, c.position.x,
        c.position.y, c.position.z);
    t.put("        uniform token[] xformOpOrder = [\"xformOp:transform\"]\n    }}\n");
}

void putSeries(Text& t, const ClipSeries& s) {
    t.put("    def {} \"{}\" (\n        clips = {{\n            dictionary default = {{\n", s.type,
          s.name);
    t.put("                double2[] active = [");
    for (std::size_t k = 0; k < s.frames.size(); ++k)
        t.put("{}({}, {})", k > 0 ? ", " : "", s.frames[k], k);
    t.put("]\n                asset[] assetPaths = [");
    for (std::size_t k = 0; k < s.frames.size(); ++k)
        t.put("{}@./{}@", k > 0 ? ", " : "", clipLayerName(s, s.frames[k]));
    t.put("]\n                asset manifestAssetPath = @./{}/manifest.usda@\n", s.directory);
    t.put("                string primPath = \"/{}\"\n", s.name);
    t.put("                double2[] times = [");
    for (std::size_t k = 0; k < s.frames.size(); ++k)
        t.put("{}({}, {})", k > 0 ? ", " : "", s.frames[k], s.frames[k]);
    t.put("]\n            }}\n        }}\n    )\n    {{\n");
    for (const std::string& declaration : s.attributes)
        t.put("        {}{}\n", declaration, declarationMetadata(declaration));
    if (s.type == "Mesh") t.put("        uniform token subdivisionScheme = \"none\"\n");
    t.put("    }}\n\n");
}

}  // namespace

std::string clipLayerName(const ClipSeries& series, int frame) {
    return fmt::format("{}/{:05d}.usda", series.directory, frame);
}

std::vector<std::string> pointsAttributes(bool velocities, bool ids, bool density, bool kind) {
    std::vector<std::string> a{"float3[] extent", "point3f[] points", "float[] widths"};
    if (ids) a.push_back("int64[] ids");
    if (velocities) a.push_back("vector3f[] velocities");
    if (density) a.push_back("float[] primvars:density");
    if (kind) a.push_back("int[] primvars:type");
    return a;
}

std::vector<std::string> meshAttributes(bool normals) {
    std::vector<std::string> a{"float3[] extent", "int[] faceVertexCounts",
                               "int[] faceVertexIndices", "point3f[] points"};
    if (normals) a.push_back("normal3f[] normals");
    return a;
}

void writePointsClip(const fs::path& path, const std::string& name, int frame,
                     const PointsFrame& p) {
    writeFileAtomically(path, [&](std::ostream& out) {
        Text t(out);
        t.put("#usda 1.0\n\ndef Points \"{}\"\n{{\n", name);
        putSample(t, "float3[] extent", frame,
                  [&] { putExtent(t, bounds(p.positions, 0.5f * p.width)); });
        if (!p.ids.empty()) putSample(t, "int64[] ids", frame, [&] { putNumberArray(t, p.ids); });
        putSample(t, "point3f[] points", frame, [&] { putVecArray(t, p.positions); });
        if (!p.density.empty())
            putSample(t, "float[] primvars:density", frame, [&] { putNumberArray(t, p.density); });
        if (!p.kind.empty())
            putSample(t, "int[] primvars:type", frame,
                      [&] { putArray(t, p.kind, [&](std::uint8_t k) { t.put("{}", int(k)); }); });
        if (!p.velocities.empty())
            putSample(t, "vector3f[] velocities", frame, [&] { putVecArray(t, p.velocities); });
        putSample(t, "float[] widths", frame, [&] {
            t.put("[");
            const std::string width = fmt::format("{}", p.width);
            for (std::size_t i = 0; i < p.positions.size(); ++i)
                t.put("{}{}", i > 0 ? ", " : "", width);
            t.put("]");
        });
        t.put("}}\n");
    });
}

void writeMeshClip(const fs::path& path, const std::string& name, int frame, const MeshData& m) {
    writeFileAtomically(path, [&](std::ostream& out) {
        Text t(out);
        t.put("#usda 1.0\n\ndef Mesh \"{}\"\n{{\n", name);
        putSample(t, "float3[] extent", frame, [&] { putExtent(t, bounds(m.vertices, 0.0f)); });
        putSample(t, "int[] faceVertexCounts", frame,
                  [&] { putFaceCounts(t, m.triangles.size()); });
        putSample(t, "int[] faceVertexIndices", frame, [&] { putFaceIndices(t, m.triangles); });
        if (!m.normals.empty())
            putSample(t, "normal3f[] normals", frame, [&] { putVecArray(t, m.normals); });
        putSample(t, "point3f[] points", frame, [&] { putVecArray(t, m.vertices); });
        t.put("}}\n");
    });
}

void writeClipManifest(const fs::path& rootDirectory, const ClipSeries& series) {
    writeFileAtomically(rootDirectory / series.directory / "manifest.usda", [&](std::ostream& out) {
        Text t(out);
        t.put("#usda 1.0\n\nover \"{}\"\n{{\n", series.name);
        for (const std::string& declaration : series.attributes) t.put("    {}\n", declaration);
        t.put("}}\n");
    });
}

void writeRootLayer(const fs::path& path, const Stage& s) {
    writeFileAtomically(path, [&](std::ostream& out) {
        Text t(out);
        t.put("#usda 1.0\n(\n    defaultPrim = \"run\"\n    doc = {}\n", quoted(s.doc));
        t.put("    endTimeCode = {}\n    framesPerSecond = {}\n", s.endFrame, s.fps);
        t.put("    metersPerUnit = 1\n    startTimeCode = {}\n", s.startFrame);
        t.put("    timeCodesPerSecond = {}\n    upAxis = \"Y\"\n)\n\n", s.fps);
        t.put("def Xform \"run\"\n{{\n");
        for (const ClipSeries& series : s.series) putSeries(t, series);
        if (!s.solids.empty()) {
            t.put("    def Scope \"solids\"\n    {{\n");
            for (std::size_t k = 0; k < s.solids.size(); ++k) {
                if (k > 0) t.put("\n");
                putStaticMesh(t, s.solids[k], "        ");
            }
            t.put("    }}\n\n");
        }
        if (!s.bodies.empty()) {
            t.put("    def Scope \"bodies\"\n    {{\n");
            for (std::size_t k = 0; k < s.bodies.size(); ++k) {
                if (k > 0) t.put("\n");
                putBody(t, s.bodies[k]);
            }
            t.put("    }}\n\n");
        }
        if (s.camera) putCamera(t, *s.camera);
        t.put("}}\n");
    });
}

}  // namespace pbf::usd
