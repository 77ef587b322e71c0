// What the README's default command leaves to look at: `pbf run` on the
// default scene (scenes/dam_break.json, output.render = spheres) run by the
// CTest fixture `run.default_scene` for a few frames into $PBF_RUN_DIR.
// Checked here: a PNG per frame, the video (or, without ffmpeg, the frames
// alone), a poster that shows the water, and the statistics plot.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <stb_image.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "pbf/io/io.hpp"
#include "pbf/io/process.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/render/frame_images.hpp"
#include "pbf/render/solid_mesh.hpp"
#include "pbf/run/run.hpp"
#include "render/image_check.hpp"

namespace pbf::render {
namespace {

namespace fs = std::filesystem;

fs::path runDirectory() {
    const char* dir = std::getenv("PBF_RUN_DIR");
    return dir != nullptr ? fs::path(dir) : fs::path();
}

std::string readBytes(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
}

Image loadPng(const fs::path& file) {
    int w = 0, h = 0, channels = 0;
    unsigned char* pixels = stbi_load(file.c_str(), &w, &h, &channels, 4);
    Image image;
    if (pixels == nullptr) return image;
    image.width = w;
    image.height = h;
    image.rgba.assign(pixels, pixels + std::size_t(w) * std::size_t(h) * 4);
    stbi_image_free(pixels);
    return image;
}

class DefaultSceneRun : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = runDirectory();
        ASSERT_FALSE(dir_.empty()) << "PBF_RUN_DIR is not set (run through ctest)";
        ASSERT_TRUE(fs::is_directory(dir_)) << dir_;
        scene_ = loadScene(std::string(PBF_SCENES_DIR) + "/dam_break.json");
        stats_ = readStatsCsv(dir_ / "stats.csv");
    }

    fs::path dir_;
    Scene scene_;
    StatsTable stats_;
};

// The share of pixels where two images differ by more than 30 (of 255) in a channel.
double differingShare(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height || a.width == 0) return 1.0;
    int differing = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) differing += image_check::difference(a, b, x, y) > 30;
    return double(differing) / (double(a.width) * double(a.height));
}

// The image written while simulating frame k is the picture of frame k's
// particles in the scene's look (output.render: spheres coloured by speed):
// rendered again here from frame_0000k.ply (the run's own particle file) it
// matches, and the neighbouring frame's particles do not. An image of the
// wrong frame, of stale particles, or in another look than the scene asks
// for fails this.
TEST_F(DefaultSceneRun, EachImageIsItsFramesParticlesInTheScenesLook) {
    ASSERT_GE(stats_.rows(), 4u);
    const ImageSettings settings = imageSettingsFor(scene_);
    const fs::path again = fs::temp_directory_path() / "pbf_run_pictures_test_again";
    auto renderPly = [&](int frame) {
        FrameImages images(settings, scene_.simulation.domain, scene_.simulation.particleRadius,
                           tessellateSolids(scene_), again);
        const ParticleFrame particles =
            readParticlesPly(dir_ / fmt::format("frame_{:05d}.ply", frame));
        images.write(frame, packParticles(particles, settings.look.color));
        return loadPng(again / imageFileName(frame));
    };
    const int frame = 3;
    const Image written = loadPng(dir_ / "images" / imageFileName(frame));
    const Image same = renderPly(frame);
    const Image previous = renderPly(frame - 1);
    fs::remove_all(again);
    const double sameShare = differingShare(written, same);
    const double previousShare = differingShare(written, previous);
    EXPECT_LT(sameShare, 0.002) << "the image of frame " << frame << " is not its particles";
    EXPECT_GT(previousShare, 10.0 * sameShare + 0.001)
        << "frames " << frame - 1 << " and " << frame << " look the same: the test cannot tell";
}

TEST_F(DefaultSceneRun, EveryFrameHasAnImageOfTheScenesSize) {
    ASSERT_GE(stats_.rows(), 3u);
    for (std::size_t frame = 0; frame < stats_.rows(); ++frame) {
        const Image image = loadPng(dir_ / "images" / imageFileName(int(frame)));
        EXPECT_EQ(image.width, scene_.output.render.width) << "frame " << frame;
        EXPECT_EQ(image.height, scene_.output.render.height) << "frame " << frame;
    }
}

TEST_F(DefaultSceneRun, VideoWhereFfmpegIsInstalled) {
    const fs::path video = dir_ / "dam_break.mp4";
    if (!findProgram("ffmpeg")) {
        EXPECT_FALSE(fs::exists(video)) << "no ffmpeg, yet a video";
        GTEST_SKIP() << "ffmpeg is not installed: the PNG frames are the output (checked above)";
    }
    ASSERT_TRUE(fs::exists(video));
    const std::string bytes = readBytes(video);
    // An MP4 starts with a box of type 'ftyp'; a few frames of H.264 take kilobytes.
    ASSERT_GT(bytes.size(), 1000u);
    EXPECT_EQ(bytes.substr(4, 4), "ftyp");
}

TEST_F(DefaultSceneRun, PosterIsTheImageOfTheFrameWithTheMostKineticEnergy) {
    const std::vector<double>& energy = stats_.column("kinetic_energy");
    std::size_t best = 0;
    for (std::size_t k = 1; k < energy.size(); ++k)
        if (energy[k] > energy[best]) best = k;
    ASSERT_GT(best, 0u) << "the water should be moving";
    const std::string poster = readBytes(dir_ / "poster.png");
    ASSERT_FALSE(poster.empty());
    EXPECT_EQ(poster, readBytes(dir_ / "images" / imageFileName(int(best))));
}

// Inside the fluid block's projection (shrunk to 40 % about its centre:
// the column has only started to fall in the few frames of the run) the
// poster differs from the image of the empty scene: the water is there.
TEST_F(DefaultSceneRun, PosterShowsTheWater) {
    const Image poster = loadPng(dir_ / "poster.png");
    ASSERT_GT(poster.width, 0);
    const ImageSettings settings = imageSettingsFor(scene_);
    ASSERT_EQ(poster.width, settings.width);
    ASSERT_EQ(poster.height, settings.height);
    const fs::path emptyDir = fs::temp_directory_path() / "pbf_run_pictures_test_empty";
    Image background;
    {
        FrameImages empty(settings, scene_.simulation.domain, scene_.simulation.particleRadius,
                          tessellateSolids(scene_), emptyDir);
        empty.write(0, RenderParticles{});
        background = loadPng(emptyDir / imageFileName(0));
    }
    fs::remove_all(emptyDir);
    const image_check::Rect inner = image_check::projectBox(
        settings.camera, scene_.fluidBlocks.front().box, 0.4f, 0, settings.width, settings.height);
    ASSERT_GT(inner.x1 - inner.x0, 20);
    ASSERT_GT(inner.y1 - inner.y0, 20);
    int water = 0, total = 0;
    for (int y = inner.y0; y < inner.y1; ++y)
        for (int x = inner.x0; x < inner.x1; ++x) {
            ++total;
            water += image_check::difference(poster, background, x, y) > 30 ? 1 : 0;
        }
    EXPECT_EQ(water, total) << "background shows through the water column";
}

TEST_F(DefaultSceneRun, StatisticsArePlotted) {
    const fs::path png = dir_ / "stats.png";
    if (!runProgram({"/usr/bin/python3", "-E", "-c", "import matplotlib"}).ok()) {
        EXPECT_FALSE(fs::exists(png));
        GTEST_SKIP() << "python3-matplotlib is not installed: no plot (the message is tested by "
                        "plot.run_without_matplotlib)";
    }
    const Image plot = loadPng(png);
    ASSERT_GT(plot.width, 0) << png << " missing or not a PNG (is python3-matplotlib installed?)";
    // Six panels of 6 x 3.6 inches at 100 dpi.
    EXPECT_GE(plot.width, 1000);
    EXPECT_GE(plot.height, 1000);
    EXPECT_TRUE(fs::exists(plot::dataFileFor(png)));
}

}  // namespace
}  // namespace pbf::render
