// The headless renderer (EGL + Mesa llvmpipe): images show the water where
// the camera sees it, and nothing else; camera and resolution validation.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>

#include "pbf/render/camera.hpp"
#include "pbf/render/headless.hpp"
#include "pbf/render/overlay.hpp"
#include "pbf/render/renderer.hpp"
#include "test_util.hpp"

namespace pbf::render {
namespace {

constexpr int kWidth = 200;
constexpr int kHeight = 120;

// Pixel rectangle [x0, x1) x [y0, y1), top row 0.
struct Rect {
    int x0, y0, x1, y1;
};

// The box's screen rectangle, projected independently of the renderer (GLM),
// scaled about its centre by `scale` and grown by `margin` pixels.
Rect projectBox(const Camera& camera, const Aabb& box, float scale, int margin) {
    const glm::mat4 view = glm::lookAt(
        glm::vec3(camera.position.x, camera.position.y, camera.position.z),
        glm::vec3(camera.target.x, camera.target.y, camera.target.z), glm::vec3(0, 1, 0));
    const glm::mat4 proj =
        glm::perspective(glm::radians(camera.fovY), float(kWidth) / kHeight, 0.01f, 100.0f);
    const Vec3 c = (box.min + box.max) * 0.5f;
    const Vec3 half = box.extent() * (0.5f * scale);
    float x0 = 1e9f, y0 = 1e9f, x1 = -1e9f, y1 = -1e9f;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p(c.x + ((corner & 1) ? half.x : -half.x),
                          c.y + ((corner & 2) ? half.y : -half.y),
                          c.z + ((corner & 4) ? half.z : -half.z));
        const glm::vec3 s = glm::project(p, view, proj, glm::vec4(0, 0, kWidth, kHeight));
        x0 = std::min(x0, s.x);
        x1 = std::max(x1, s.x);
        y0 = std::min(y0, kHeight - s.y);
        y1 = std::max(y1, kHeight - s.y);
    }
    return {int(std::floor(x0)) - margin, int(std::floor(y0)) - margin, int(std::ceil(x1)) + margin,
            int(std::ceil(y1)) + margin};
}

int difference(const Image& a, const Image& b, int x, int y) {
    const std::size_t i = (std::size_t(y) * std::size_t(a.width) + std::size_t(x)) * 4;
    int d = 0;
    for (int k = 0; k < 3; ++k) d += std::abs(int(a.rgba[i + k]) - int(b.rgba[i + k]));
    return d;
}

class HeadlessRenderTest : public ::testing::Test {
  protected:
    void SetUp() override {
        scene_ = loadScene(test::scenePath("cube_drop.json"));
        block_ = scene_.fluidBlocks.front().box;
        camera_ = frameBox(scene_.simulation.domain, float(kWidth) / kHeight);
    }

    Image render(const RenderParticles& particles, const RenderSettings& settings) {
        SceneRenderer renderer;
        renderer.setDomain(scene_.simulation.domain);
        renderer.setParticleRadius(scene_.simulation.particleRadius);
        renderer.upload(particles);
        OffscreenTarget target(kWidth, kHeight);
        renderer.render(target.framebuffer(), kWidth, kHeight, camera_, settings);
        return target.read();
    }

    // Inside the block's projection the water covers the background; outside
    // it (beyond one particle diameter) the image is exactly the background.
    void expectWaterWhereTheBlockIs(const RenderSettings& settings, const Image& water) {
        const Image background = render(RenderParticles{}, settings);
        ASSERT_EQ(water.width, kWidth);
        ASSERT_EQ(water.height, kHeight);
        const Rect inner = projectBox(camera_, block_, 0.4f, 0);
        const Rect outer = projectBox(camera_, block_, 1.0f, 4);
        ASSERT_GT(inner.x1 - inner.x0, 4);
        ASSERT_GT(inner.y1 - inner.y0, 4);
        int insideWater = 0, insideTotal = 0, outsideChanged = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                const int d = difference(water, background, x, y);
                if (x >= inner.x0 && x < inner.x1 && y >= inner.y0 && y < inner.y1) {
                    ++insideTotal;
                    insideWater += d > 30 ? 1 : 0;
                } else if (x < outer.x0 || x >= outer.x1 || y < outer.y0 || y >= outer.y1) {
                    outsideChanged += d > 0 ? 1 : 0;
                }
            }
        EXPECT_EQ(insideWater, insideTotal) << "background shows through the block";
        EXPECT_EQ(outsideChanged, 0) << "pixels changed away from the block";
    }

    Scene scene_;
    Aabb block_;
    Camera camera_;
    HeadlessContext context_;
};

TEST_F(HeadlessRenderTest, SpheresInFlatColourCoverTheBlockOnly) {
    RenderSettings settings;
    settings.color = ColorMode::Flat;
    const Image image = render(packParticles(createParticles(scene_), ColorMode::Flat), settings);
    expectWaterWhereTheBlockIs(settings, image);
    // The flat colour is blue: at the block's centre blue dominates red.
    const Rect inner = projectBox(camera_, block_, 0.1f, 0);
    const std::size_t i =
        (std::size_t((inner.y0 + inner.y1) / 2) * kWidth + std::size_t((inner.x0 + inner.x1) / 2)) *
        4;
    EXPECT_GT(int(image.rgba[i + 2]), int(image.rgba[i + 0]) + 60);
}

TEST_F(HeadlessRenderTest, SpeedColoursFollowTheColourMap) {
    ParticleStore particles = createParticles(scene_);
    RenderSettings settings;
    settings.rangeMin = 0.0f;
    settings.rangeMax = 2.0f;
    // At rest every particle has the colour map's low end (blue); at 2 m/s its high end (red).
    const Rect inner = projectBox(camera_, block_, 0.1f, 0);
    const std::size_t i =
        (std::size_t((inner.y0 + inner.y1) / 2) * kWidth + std::size_t((inner.x0 + inner.x1) / 2)) *
        4;
    const Image slow = render(packParticles(particles, ColorMode::Speed), settings);
    expectWaterWhereTheBlockIs(settings, slow);
    EXPECT_GT(int(slow.rgba[i + 2]), int(slow.rgba[i + 0]) + 60);
    for (std::size_t k = 0; k < particles.size(); ++k)
        particles.velocity.set(k, {0.0f, -2.0f, 0.0f});
    const Image fast = render(packParticles(particles, ColorMode::Speed), settings);
    EXPECT_GT(int(fast.rgba[i + 0]), int(fast.rgba[i + 2]) + 60);
}

TEST_F(HeadlessRenderTest, LiquidLookCoversTheBlockOnly) {
    RenderSettings settings;
    settings.style = Style::Liquid;
    const Image image = render(packParticles(createParticles(scene_), ColorMode::Speed), settings);
    expectWaterWhereTheBlockIs(settings, image);
}

TEST_F(HeadlessRenderTest, PngRoundTrip) {
    RenderSettings settings;
    const Image image = render(packParticles(createParticles(scene_), ColorMode::Speed), settings);
    const auto path = std::filesystem::temp_directory_path() / "pbf_render_test.png";
    writePng(path, image);
    int w = 0, h = 0, channels = 0;
    unsigned char* pixels = stbi_load(path.c_str(), &w, &h, &channels, 4);
    ASSERT_NE(pixels, nullptr);
    EXPECT_EQ(w, kWidth);
    EXPECT_EQ(h, kHeight);
    EXPECT_TRUE(std::equal(image.rgba.begin(), image.rgba.end(), pixels));
    stbi_image_free(pixels);
    std::filesystem::remove(path);
}

TEST_F(HeadlessRenderTest, ColorBarOverlayDrawsInTheTopLeftCornerOnly) {
    RenderSettings settings;
    const RenderParticles particles = packParticles(createParticles(scene_), ColorMode::Speed);
    const Image plain = render(particles, settings);
    SceneRenderer renderer;
    renderer.setDomain(scene_.simulation.domain);
    renderer.setParticleRadius(scene_.simulation.particleRadius);
    renderer.upload(particles);
    OffscreenTarget target(kWidth, kHeight);
    ColorBarOverlay overlay;
    renderer.render(target.framebuffer(), kWidth, kHeight, camera_, settings);
    overlay.draw(target.framebuffer(), kWidth, kHeight, settings);
    const Image withBar = target.read();
    int changedTopLeft = 0, changedElsewhere = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            // The overlay: 8 px from the corner, 45 % of the width, three lines high.
            const bool topLeft = x < 130 && y < 90;
            (topLeft ? changedTopLeft : changedElsewhere) +=
                difference(withBar, plain, x, y) > 0 ? 1 : 0;
        }
    EXPECT_GT(changedTopLeft, 500);
    EXPECT_EQ(changedElsewhere, 0);
    // Flat colours have no colour bar.
    settings.color = ColorMode::Flat;
    renderer.render(target.framebuffer(), kWidth, kHeight, camera_, settings);
    overlay.draw(target.framebuffer(), kWidth, kHeight, settings);
    const Image flat = target.read();
    const Image flatPlain =
        render(packParticles(createParticles(scene_), ColorMode::Flat), settings);
    EXPECT_TRUE(flat.rgba == flatPlain.rgba);
}

TEST(Camera, ValidationNamesTheField) {
    Camera camera;
    EXPECT_EQ(validateCamera(camera), "");
    camera.fovY = 0.0f;
    EXPECT_NE(validateCamera(camera).find("camera.fov"), std::string::npos);
    camera.fovY = 200.0f;
    EXPECT_NE(validateCamera(camera).find("camera.fov"), std::string::npos);
    camera.fovY = 45.0f;
    camera.position = camera.target;
    EXPECT_NE(validateCamera(camera).find("must differ"), std::string::npos);
    camera.position = camera.target + Vec3{0.0f, 2.0f, 0.0f};
    EXPECT_NE(validateCamera(camera).find("vertical"), std::string::npos);
    camera.position = {NAN, 0.0f, 0.0f};
    EXPECT_NE(validateCamera(camera).find("finite"), std::string::npos);
    EXPECT_EQ(validateResolution(640, 480), "");
    EXPECT_NE(validateResolution(0, 480).find("width"), std::string::npos);
    EXPECT_NE(validateResolution(640, 100000).find("height"), std::string::npos);
}

TEST(Camera, FrameBoxSeesTheWholeBoxAndOrbitKeepsIt) {
    const Aabb box{{0, 0, 0}, {1.6f, 1.0f, 0.4f}};
    const Camera camera = frameBox(box, float(kWidth) / kHeight);
    EXPECT_EQ(validateCamera(camera), "");
    const Rect r = projectBox(camera, box, 1.0f, 0);
    EXPECT_GE(r.x0, 0);
    EXPECT_LE(r.x1, kWidth);
    EXPECT_GE(r.y0, 0);
    EXPECT_LE(r.y1, kHeight);
    const Camera again = OrbitCamera(camera).camera();
    EXPECT_NEAR(again.position.x, camera.position.x, 1e-4f);
    EXPECT_NEAR(again.position.y, camera.position.y, 1e-4f);
    EXPECT_NEAR(again.position.z, camera.position.z, 1e-4f);
    OrbitCamera orbit(camera);
    orbit.orbit(90.0f, 0.0f);
    const float before = length(camera.position - camera.target);
    const Camera turned = orbit.camera();
    EXPECT_NEAR(length(turned.position - turned.target), before, 1e-4f);
    EXPECT_GT(std::abs(turned.position.x - camera.position.x), 0.1f);
}

TEST(RenderSettings, NamesParseAndRoundTrip) {
    EXPECT_EQ(parseStyle("liquid"), Style::Liquid);
    EXPECT_EQ(parseColorMode("density"), ColorMode::Density);
    EXPECT_STREQ(toString(parseColorMode("flat")), "flat");
    EXPECT_THROW(parseStyle("glass"), std::invalid_argument);
    EXPECT_THROW(parseColorMode("rainbow"), std::invalid_argument);
}

}  // namespace
}  // namespace pbf::render
