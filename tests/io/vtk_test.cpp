// VTK XML files and .pvd collections (include/pbf/io/vtk.hpp), read back here by
// a parser of the test's own; tests/clients/paraview_test.py opens the same
// files in ParaView.
#include "pbf/io/vtk.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
// GCC 12 at -O2 with the sanitizers warns "may be used uninitialized" inside
// libstdc++'s <regex> (a false positive: GCC bug 105562); -Werror would turn
// it into a failed asan build.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <regex>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#include <string>
#include <vector>

#include "pbf/io/io.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/run/run.hpp"
#include "support/test_util.hpp"

namespace {

namespace fs = std::filesystem;

using pbf::test::freshDirectory;

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

// The appended arrays of a VTK XML file: name -> (type, components, raw bytes).
struct ParsedArray {
    std::string type;
    int components = 1;
    std::string bytes;
    template <typename T>
    std::vector<T> values() const {
        std::vector<T> v(bytes.size() / sizeof(T));
        std::memcpy(v.data(), bytes.data(), bytes.size());
        return v;
    }
};

std::map<std::string, ParsedArray> parseAppended(const std::string& file) {
    std::map<std::string, ParsedArray> arrays;
    const std::size_t start = file.find("<AppendedData encoding=\"raw\">");
    EXPECT_NE(start, std::string::npos);
    const std::size_t base = file.find('_', start) + 1;  // offsets count from after '_'
    const std::regex tag(
        R"re(<DataArray type="(\w+)" Name="(\w+)"(?: NumberOfComponents="(\d+)")? format="appended" offset="(\d+)"/>)re");
    const std::string xml = file.substr(0, start);
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), tag); it != std::sregex_iterator();
         ++it) {
        const std::smatch& m = *it;
        ParsedArray a;
        a.type = m[1];
        if (m[3].matched) a.components = std::stoi(m[3]);
        const std::size_t at = base + std::stoull(m[4]);
        std::uint64_t size = 0;
        std::memcpy(&size, file.data() + at, 8);
        EXPECT_LE(at + 8 + size, file.size()) << m[2];
        a.bytes = file.substr(at + 8, size);
        arrays[m[2]] = a;
    }
    return arrays;
}

TEST(Vtk, ParticlesAreVertexCellsWithEveryAttributeInIdOrder) {
    pbf::ParticleStore p;
    // Ids from 2^32 - 50: the file keeps all 64 bits.
    constexpr std::uint64_t kFirstId = (std::uint64_t{1} << 32) - 50;
    p.setNextId(kFirstId);
    for (int k = 0; k < 100; ++k) {
        const float f = float(k);
        p.add({0.01f * f, 0.5f, -0.25f * f}, {f, -1.0f, 2.0f}, 1000.0f + f);
    }
    std::vector<std::uint32_t> perm(100);
    for (std::uint32_t k = 0; k < 100; ++k) perm[k] = (k * 37) % 100;
    p.reorder(perm);  // memory order as the solver leaves it
    const fs::path dir = freshDirectory("vtu");
    pbf::vtk::writeParticlesVtu(dir / "f.vtu", p, 0.5);
    const std::string file = readText(dir / "f.vtu");
    EXPECT_NE(
        file.find(
            R"(<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">)"),
        std::string::npos);
    EXPECT_NE(file.find(R"(<Piece NumberOfPoints="100" NumberOfCells="100">)"), std::string::npos);
    EXPECT_NE(file.find(R"(Name="TimeValue" NumberOfTuples="1" format="ascii">0.5<)"),
              std::string::npos);
    EXPECT_TRUE(file.ends_with("</AppendedData>\n</VTKFile>\n"));

    const auto arrays = parseAppended(file);
    ASSERT_EQ(arrays.size(), 7u);
    EXPECT_EQ(arrays.at("velocity").components, 3);
    EXPECT_EQ(arrays.at("Points").components, 3);
    EXPECT_EQ(arrays.at("id").type, "UInt64");
    EXPECT_EQ(arrays.at("connectivity").type, "Int32");
    const auto x = arrays.at("Points").values<float>();
    const auto v = arrays.at("velocity").values<float>();
    const auto rho = arrays.at("density").values<float>();
    const auto id = arrays.at("id").values<std::uint64_t>();
    const auto connectivity = arrays.at("connectivity").values<std::int32_t>();
    const auto offsets = arrays.at("offsets").values<std::int32_t>();
    const auto types = arrays.at("types").values<std::uint8_t>();
    ASSERT_EQ(x.size(), 300u);
    ASSERT_EQ(types.size(), 100u);
    for (std::uint32_t k = 0; k < 100; ++k) {
        const float f = float(k);
        EXPECT_EQ(id[k], kFirstId + k);
        EXPECT_EQ(x[3 * k], 0.01f * f);
        EXPECT_EQ(x[3 * k + 2], -0.25f * f);
        EXPECT_EQ(v[3 * k], f);
        EXPECT_EQ(v[3 * k + 1], -1.0f);
        EXPECT_EQ(rho[k], 1000.0f + f);
        EXPECT_EQ(connectivity[k], std::int32_t(k));
        EXPECT_EQ(offsets[k], std::int32_t(k + 1));
        EXPECT_EQ(types[k], 1);  // VTK_VERTEX
    }
    fs::remove_all(dir);
}

// After an outlet removed particles the ids have gaps (and the memory order
// is the solver's): the points are still in id order, every field follows
// its particle, and the cells number the points that are left, 0 .. n - 1.
TEST(Vtk, ParticlesWithGapsInTheirIdsAreWrittenInIdOrder) {
    pbf::ParticleStore p;
    for (int k = 0; k < 90; ++k) p.add({0.01f * float(k), 0.0f, 0.0f}, {float(k), 0, 0}, 1000.0f);
    std::vector<std::uint32_t> perm(90);
    for (std::uint32_t k = 0; k < 90; ++k) perm[k] = (k * 37) % 90;
    p.reorder(perm);
    std::vector<std::uint32_t> kept;  // every particle whose id is not a multiple of 3
    for (std::uint32_t i = 0; i < 90; ++i)
        if (p.id[i] % 3 != 0) kept.push_back(i);
    p.keepOnly(kept);
    ASSERT_EQ(p.size(), 60u);
    const fs::path dir = freshDirectory("vtu_gaps");
    pbf::vtk::writeParticlesVtu(dir / "f.vtu", p, 0.0);
    const auto arrays = parseAppended(readText(dir / "f.vtu"));
    const auto x = arrays.at("Points").values<float>();
    const auto v = arrays.at("velocity").values<float>();
    const auto id = arrays.at("id").values<std::uint64_t>();
    const auto connectivity = arrays.at("connectivity").values<std::int32_t>();
    ASSERT_EQ(id.size(), 60u);
    for (std::uint32_t k = 0; k < 60; ++k) {
        const std::uint64_t expected = 3 * (k / 2) + 1 + k % 2;  // 1, 2, 4, 5, 7, ...
        EXPECT_EQ(id[k], expected);
        EXPECT_EQ(x[3 * k], 0.01f * float(expected));
        EXPECT_EQ(v[3 * k], float(expected));
        EXPECT_EQ(connectivity[k], std::int32_t(k));
    }
    fs::remove_all(dir);
}

TEST(Vtk, TrianglesWithNormals) {
    const std::vector<pbf::Vec3> vertices{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    const std::vector<pbf::Vec3> normals(4, pbf::Vec3{0, 0, 1});
    const std::vector<std::array<std::uint32_t, 3>> triangles{{0, 1, 2}, {2, 1, 3}};
    const fs::path dir = freshDirectory("vtp");
    pbf::vtk::writeTrianglesVtp(dir / "m.vtp", vertices, normals, triangles, 1.0 / 30.0);
    const std::string file = readText(dir / "m.vtp");
    EXPECT_NE(
        file.find(
            R"(NumberOfPoints="4" NumberOfVerts="0" NumberOfLines="0" NumberOfStrips="0" NumberOfPolys="2")"),
        std::string::npos);
    const auto arrays = parseAppended(file);
    EXPECT_EQ(arrays.at("Normals").values<float>(),
              (std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}));
    EXPECT_EQ(arrays.at("Points").values<float>().size(), 12u);
    EXPECT_EQ(arrays.at("connectivity").values<std::int32_t>(),
              (std::vector<std::int32_t>{0, 1, 2, 2, 1, 3}));
    EXPECT_EQ(arrays.at("offsets").values<std::int32_t>(), (std::vector<std::int32_t>{3, 6}));
    // Normals must match the vertices one to one.
    EXPECT_THROW(pbf::vtk::writeTrianglesVtp(dir / "bad.vtp", vertices, std::span(normals).first(3),
                                             triangles, 0.0),
                 pbf::IoError);
    fs::remove_all(dir);
}

// The DataSet lines of a collection as (time text, file).
std::vector<std::pair<std::string, std::string>> collection(const fs::path& pvd) {
    const std::string text = readText(pvd);
    EXPECT_TRUE(text.ends_with("  </Collection>\n</VTKFile>\n")) << text;
    std::vector<std::pair<std::string, std::string>> entries;
    const std::regex line(R"re(<DataSet timestep="([^"]+)" part="0" file="([^"]+)"/>)re");
    for (auto it = std::sregex_iterator(text.begin(), text.end(), line);
         it != std::sregex_iterator(); ++it)
        entries.emplace_back((*it)[1], (*it)[2]);
    return entries;
}

TEST(Vtk, CollectionIsWrittenWholeThenAppendedTo) {
    const fs::path dir = freshDirectory("pvd");
    const fs::path pvd = dir / "c.pvd";
    pbf::vtk::writeCollection(pvd, {{0.0, "a_0.vtu"}});
    pbf::vtk::appendToCollection(pvd, {1.0 / 30.0, "a_1.vtu"});
    pbf::vtk::appendToCollection(pvd, {2.0 / 30.0, "a&<2>.vtu"});
    const auto entries = collection(pvd);
    ASSERT_EQ(entries.size(), 3u);
    EXPECT_EQ(std::stod(entries[1].first), 1.0 / 30.0);  // shortest text that reads back exactly
    EXPECT_EQ(entries[2].second, "a&amp;&lt;2&gt;.vtu");
    // A file that is not a collection of ours is not appended to.
    std::ofstream(dir / "other.pvd") << "<VTKFile/>\n";
    try {
        pbf::vtk::appendToCollection(dir / "other.pvd", {0.0, "x.vtu"});
        FAIL() << "appended to a foreign file";
    } catch (const pbf::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("other.pvd: not a collection written by pbf"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_THROW(pbf::vtk::appendToCollection(dir / "missing.pvd", {0.0, "x.vtu"}), pbf::IoError);
    fs::remove_all(dir);
}

// output.vtk through runScene: a .vtu per frame, particles.pvd with the frame
// times; a resume from an older checkpoint (as after a kill: frames after it
// were written and listed) lists every frame once.
TEST(Vtk, RunWritesFramesAndACollectionThatSurvivesAResume) {
    const fs::path dir = freshDirectory("vtk_run");
    pbf::Scene scene = pbf::parseScene(
        pbf::test::smallSceneJson(R"("output": {"fps": 30, "frames": 2, "vtk": true})"),
        "small.json");
    scene.output.directory = dir.string();
    pbf::runScene(scene, {});
    fs::copy_file(dir / "checkpoint.pbfck", dir / "frame2.pbfck");
    scene.output.frames = 4;
    pbf::RunOptions resume;
    resume.resume = true;
    pbf::runScene(scene, resume);  // frames 3, 4 appended
    EXPECT_EQ(collection(dir / "particles.pvd").size(), 5u);
    fs::copy_file(dir / "frame2.pbfck", dir / "checkpoint.pbfck",
                  fs::copy_options::overwrite_existing);
    pbf::runScene(scene, resume);  // as if killed after frame 4 with the checkpoint of frame 2
    const auto entries = collection(dir / "particles.pvd");
    ASSERT_EQ(entries.size(), 5u);
    for (int k = 0; k <= 4; ++k) {
        EXPECT_EQ(entries[k].second, pbf::frameFileName(k).replace_extension(".vtu").string());
        EXPECT_EQ(std::stod(entries[k].first), k / 30.0);
        EXPECT_TRUE(fs::exists(dir / entries[k].second));
    }
    fs::remove_all(dir);
}

}  // namespace
