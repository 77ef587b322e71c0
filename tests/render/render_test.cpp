// The headless renderer (EGL + Mesa llvmpipe): images show the water where
// the camera sees it, and nothing else; camera and resolution validation.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "pbf/render/camera.hpp"
#include "pbf/render/headless.hpp"
#include "pbf/render/overlay.hpp"
#include "pbf/render/renderer.hpp"
#include "pbf/render/solid_mesh.hpp"
#include "render/image_check.hpp"
#include "support/test_util.hpp"

namespace pbf::render {
namespace {

constexpr int kWidth = 200;
constexpr int kHeight = 120;

using image_check::difference;
using image_check::Rect;

// The box's screen rectangle in a kWidth x kHeight image (image_check.hpp).
Rect projectBox(const Camera& camera, const Aabb& box, float scale, int margin) {
    return image_check::projectBox(camera, box, scale, margin, kWidth, kHeight);
}

class HeadlessRenderTest : public ::testing::Test {
  protected:
    void SetUp() override {
        scene_ = loadScene(test::scenePath("cube_drop.json"));
        block_ = scene_.fluidBlocks.front().box;
        camera_ = frameBox(scene_.simulation.domain, float(kWidth) / kHeight);
    }

    Image render(const RenderParticles& particles, const RenderSettings& settings,
                 const SolidMesh* solids = nullptr, const RenderParticles* diffuse = nullptr) {
        SceneRenderer renderer;
        renderer.setDomain(scene_.simulation.domain);
        renderer.setParticleRadius(scene_.simulation.particleRadius);
        if (solids) renderer.setSolids(*solids);
        renderer.upload(particles);
        if (diffuse) renderer.uploadDiffuse(*diffuse);
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

// Far from the origin a float's spacing reaches the pixels (1 mm at 10 km)
// and a view matrix there loses the scene (spheres vanished, bodies drew as
// shards): the renderer draws relative to the World's local frame, so the
// same block 10 km away looks the same.
TEST_F(HeadlessRenderTest, TheSameBlockTenKilometresAwayLooksTheSame) {
    const Vec3 offset{10000.0f, 0.0f, -10000.0f};
    const auto shift = [&](const Vec3& p) {
        return Vec3{float(double(p.x) + double(offset.x)), float(double(p.y) + double(offset.y)),
                    float(double(p.z) + double(offset.z))};
    };
    ParticleStore near = createParticles(scene_);
    ParticleStore far = near;
    for (std::size_t k = 0; k < far.size(); ++k) far.position.set(k, shift(far.position.get(k)));
    for (const Style style : {Style::Spheres, Style::Liquid}) {
        RenderSettings settings;
        settings.style = style;
        const Image here = render(packParticles(near, ColorMode::Speed), settings);
        const Aabb domain = scene_.simulation.domain;
        const Camera camera = camera_;
        scene_.simulation.domain = {shift(domain.min), shift(domain.max)};
        camera_.position = shift(camera.position);
        camera_.target = shift(camera.target);
        const Image there = render(packParticles(far, ColorMode::Speed), settings);
        scene_.simulation.domain = domain;
        camera_ = camera;
        int changed = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) changed += difference(here, there, x, y) > 30 ? 1 : 0;
        // The particles' world floats there are rounded by up to 0.5 mm.
        EXPECT_LT(changed, kWidth * kHeight / 100) << toString(style);
    }
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

// A box solid in the cube drop's domain, away from the water block.
constexpr Aabb kSolidBox{{0.10f, 0.05f, 0.60f}, {0.30f, 0.35f, 0.85f}};

SolidMesh boxSolidMesh(const Aabb& box) {
    SolidDescription solid;
    solid.kind = SolidDescription::Kind::Box;
    solid.box = box;
    SolidMesh mesh;
    appendSolid(mesh, solid, Aabb{{0, 0, 0}, {1, 1, 1}});
    return mesh;
}

bool inside(const Rect& r, int x, int y) {
    return x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1;
}

// Without water, a box solid covers its screen rectangle in stone grey and
// leaves the rest of the image exactly as it was, in both looks.
TEST_F(HeadlessRenderTest, SolidBoxIsDrawnWhereItStandsOnly) {
    const SolidMesh solid = boxSolidMesh(kSolidBox);
    const Rect innerRect = projectBox(camera_, kSolidBox, 0.4f, 0);
    const Rect outerRect = projectBox(camera_, kSolidBox, 1.0f, 2);
    ASSERT_GT(innerRect.x1 - innerRect.x0, 4);
    ASSERT_GT(innerRect.y1 - innerRect.y0, 4);
    for (const Style style : {Style::Spheres, Style::Liquid}) {
        SCOPED_TRACE(toString(style));
        RenderSettings settings;
        settings.style = style;
        const Image empty = render(RenderParticles{}, settings);
        const Image withSolid = render(RenderParticles{}, settings, &solid);
        int insideTotal = 0, insideGrey = 0, outsideChanged = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                if (inside(innerRect, x, y)) {
                    ++insideTotal;
                    const std::size_t i = (std::size_t(y) * kWidth + std::size_t(x)) * 4;
                    const int r = withSolid.rgba[i], g = withSolid.rgba[i + 1],
                              b = withSolid.rgba[i + 2];
                    // Grey: channels within a few levels of each other (the sky is blue,
                    // the floor lighter), and different from the empty image.
                    const bool grey = std::abs(r - g) < 16 && std::abs(g - b) < 16 &&
                                      std::abs(r - b) < 16 && r > 40 && r < 200;
                    insideGrey += grey && difference(withSolid, empty, x, y) > 30 ? 1 : 0;
                } else if (!inside(outerRect, x, y)) {
                    outsideChanged += difference(withSolid, empty, x, y) > 0 ? 1 : 0;
                }
            }
        EXPECT_EQ(insideGrey, insideTotal) << "the solid does not cover its rectangle";
        EXPECT_EQ(outsideChanged, 0) << "pixels changed away from the solid";
    }
}

// A solid in front of the water hides it: where both project, the image with
// water is exactly the image without, and the solid is not see-through.
TEST_F(HeadlessRenderTest, SolidInFrontHidesTheWater) {
    // A cube of 0.13 m on the line from the block's centre to the camera.
    const Vec3 blockCentre = (block_.min + block_.max) * 0.5f;
    const Vec3 toCamera = camera_.position - blockCentre;
    const Vec3 centre = blockCentre + toCamera * (0.4f / length(toCamera));
    const Vec3 half{0.065f, 0.065f, 0.065f};
    const Aabb solidBox{centre - half, centre + half};
    const SolidMesh solid = boxSolidMesh(solidBox);
    const Rect s = projectBox(camera_, solidBox, 0.4f, 0);
    const Rect w = projectBox(camera_, block_, 0.4f, 0);
    const Rect both{std::max(s.x0, w.x0), std::max(s.y0, w.y0), std::min(s.x1, w.x1),
                    std::min(s.y1, w.y1)};
    ASSERT_GT(both.x1 - both.x0, 4) << "the solid must stand in front of the block";
    ASSERT_GT(both.y1 - both.y0, 4) << "the solid must stand in front of the block";
    const ParticleStore particles = createParticles(scene_);
    for (const Style style : {Style::Spheres, Style::Liquid}) {
        SCOPED_TRACE(toString(style));
        RenderSettings settings;
        settings.style = style;
        settings.color = ColorMode::Flat;
        const RenderParticles water = packParticles(particles, ColorMode::Flat);
        const Image solidOnly = render(RenderParticles{}, settings, &solid);
        const Image waterOnly = render(water, settings);
        const Image solidAndWater = render(water, settings, &solid);
        int total = 0, hidden = 0, covered = 0, waterElsewhere = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                if (inside(both, x, y)) {
                    ++total;
                    hidden += difference(solidAndWater, solidOnly, x, y) == 0 ? 1 : 0;
                    covered += difference(solidAndWater, waterOnly, x, y) > 30 ? 1 : 0;
                } else if (inside(projectBox(camera_, block_, 1.0f, 0), x, y) &&
                           !inside(projectBox(camera_, solidBox, 1.0f, 2), x, y)) {
                    // Water not behind the solid is still drawn.
                    waterElsewhere += difference(solidAndWater, solidOnly, x, y) > 30 ? 1 : 0;
                }
            }
        EXPECT_EQ(hidden, total) << "water shows through the solid";
        EXPECT_EQ(covered, total) << "the solid does not cover the water";
        EXPECT_GT(waterElsewhere, 50);
    }
}

// White water (pbf foam's diffuse particles): a cube of them, no fluid, in
// both looks. Inside its projection (shrunk to 40 %) every pixel turns light
// (each channel at least 170, well above the floor's and the sky's grey-blue
// mix... and different from the empty image); outside it plus 3 pixels
// nothing changes. An empty diffuse upload changes nothing at all.
TEST_F(HeadlessRenderTest, WhiteWaterIsDrawnWhereDiffuseParticlesAreOnly) {
    const Aabb cloud{{0.45f, 0.45f, 0.45f}, {0.55f, 0.55f, 0.55f}};
    std::vector<Vec3> positions;
    std::vector<std::uint8_t> types;
    const float spacing = 0.6f * scene_.simulation.particleRadius;
    for (float x = cloud.min.x; x <= cloud.max.x; x += spacing)
        for (float y = cloud.min.y; y <= cloud.max.y; y += spacing)
            for (float z = cloud.min.z; z <= cloud.max.z; z += spacing) {
                positions.push_back({x, y, z});
                types.push_back(std::uint8_t(positions.size() % 2));  // spray and foam
            }
    const RenderParticles diffuse = packDiffuse(positions, types);
    const Rect inner = projectBox(camera_, cloud, 0.4f, 0);
    const Rect outer = projectBox(camera_, cloud, 1.0f, 3);
    for (const Style style : {Style::Spheres, Style::Liquid}) {
        SCOPED_TRACE(toString(style));
        RenderSettings settings;
        settings.style = style;
        const Image background = render(RenderParticles{}, settings);
        const RenderParticles none;
        const Image empty = render(RenderParticles{}, settings, nullptr, &none);
        EXPECT_EQ(empty.rgba, background.rgba);
        const Image white = render(RenderParticles{}, settings, nullptr, &diffuse);
        int light = 0, total = 0, changedOutside = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                const std::size_t i = (std::size_t(y) * kWidth + std::size_t(x)) * 4;
                if (x >= inner.x0 && x < inner.x1 && y >= inner.y0 && y < inner.y1) {
                    ++total;
                    light += white.rgba[i] >= 170 && white.rgba[i + 1] >= 170 &&
                                     white.rgba[i + 2] >= 170 &&
                                     difference(white, background, x, y) > 0
                                 ? 1
                                 : 0;
                } else if (x < outer.x0 || x >= outer.x1 || y < outer.y0 || y >= outer.y1) {
                    changedOutside += difference(white, background, x, y) > 0 ? 1 : 0;
                }
            }
        ASSERT_GT(total, 16);
        EXPECT_EQ(light, total) << "white water missing inside the cloud's projection";
        EXPECT_EQ(changedOutside, 0) << "pixels changed away from the cloud";
    }
}

// In the liquid look, foam lying on the water's surface is seen (its depth is
// biased towards the camera past the smoothed surface), and bubbles deep
// inside the block are not.
TEST_F(HeadlessRenderTest, LiquidLookShowsFoamOnTheSurfaceAndHidesDeepBubbles) {
    RenderSettings settings;
    settings.style = Style::Liquid;
    const RenderParticles water = packParticles(createParticles(scene_), ColorMode::Speed);
    const Image plain = render(water, settings);
    const float r = scene_.simulation.particleRadius;
    // A square of foam on the block's top face, and bubbles at its centre.
    const Vec3 c = (block_.min + block_.max) * 0.5f;
    std::vector<Vec3> foam, bubbles;
    for (float x = c.x - 0.05f; x <= c.x + 0.05f; x += 0.6f * r)
        for (float z = c.z - 0.05f; z <= c.z + 0.05f; z += 0.6f * r) {
            foam.push_back({x, block_.max.y, z});
            bubbles.push_back({x, c.y, z});
        }
    const RenderParticles foamPacked =
        packDiffuse(foam, std::vector<std::uint8_t>(foam.size(), std::uint8_t(1)));
    const RenderParticles bubblesPacked =
        packDiffuse(bubbles, std::vector<std::uint8_t>(bubbles.size(), std::uint8_t(2)));
    const Image withFoam = render(water, settings, nullptr, &foamPacked);
    const Image withBubbles = render(water, settings, nullptr, &bubblesPacked);
    const Rect top = projectBox(
        camera_,
        Aabb{{c.x - 0.05f, block_.max.y, c.z - 0.05f}, {c.x + 0.05f, block_.max.y, c.z + 0.05f}},
        0.4f, 0);
    int light = 0, total = 0;
    for (int y = top.y0; y < top.y1; ++y)
        for (int x = top.x0; x < top.x1; ++x) {
            ++total;
            const std::size_t i = (std::size_t(y) * kWidth + std::size_t(x)) * 4;
            light += withFoam.rgba[i] >= 170 && withFoam.rgba[i + 1] >= 170 &&
                             withFoam.rgba[i + 2] >= 170 && difference(withFoam, plain, x, y) > 30
                         ? 1
                         : 0;
        }
    ASSERT_GT(total, 4);
    EXPECT_GE(light, total * 9 / 10) << "foam on the surface is hidden";
    EXPECT_EQ(withBubbles.rgba, plain.rgba) << "bubbles deep inside the water are drawn";
}

// A stream one particle wide (particles 2 r apart on a vertical line) is a
// visible line of water in the liquid look: at the screen position of every
// particle but the two ends, the image differs from the empty scene by more
// than 30 (sum over R, G, B), also between two particles.
TEST_F(HeadlessRenderTest, LiquidLookShowsAThinStream) {
    const float r = scene_.simulation.particleRadius;
    ParticleFrame stream;
    std::vector<Vec3> samples;
    for (float y = 0.3f; y <= 0.9f; y += 2.0f * r) {
        stream.position.push_back({0.5f, y, 0.5f});
        if (y > 0.33f && y < 0.87f) {
            samples.push_back({0.5f, y, 0.5f});
            samples.push_back({0.5f, y + r, 0.5f});  // halfway to the next
        }
    }
    RenderSettings settings;
    settings.style = Style::Liquid;
    const Image background = render(RenderParticles{}, settings);
    const Image image = render(packParticles(stream, ColorMode::Speed), settings);
    int visible = 0;
    for (const Vec3& p : samples) {
        const Rect at = projectBox(camera_, Aabb{p, p}, 1.0f, 0);
        const int x = std::clamp((at.x0 + at.x1) / 2, 0, kWidth - 1);
        const int y = std::clamp((at.y0 + at.y1) / 2, 0, kHeight - 1);
        visible += difference(image, background, x, y) > 30 ? 1 : 0;
    }
    EXPECT_EQ(visible, int(samples.size())) << "the stream is invisible in places";
}

TEST(SolidMesh, AnalyticShapesAreTessellatedOnTheirSurfaces) {
    const Aabb domain{{0, 0, 0}, {1, 1, 1}};
    SolidDescription box;
    box.kind = SolidDescription::Kind::Box;
    box.box = {{0.1f, 0.2f, 0.3f}, {0.4f, 0.5f, 0.6f}};
    SolidMesh mesh;
    appendSolid(mesh, box, domain);
    ASSERT_EQ(mesh.triangleCount(), 12u);
    for (std::size_t v = 0; v < 36; ++v) {
        const Vec3 p = mesh.position(v);
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(p[k] == box.box.min[k] || p[k] == box.box.max[k]);
    }

    SolidDescription sphere;
    sphere.kind = SolidDescription::Kind::Sphere;
    sphere.center = {0.5f, 0.4f, 0.3f};
    sphere.radius = 0.2f;
    mesh = {};
    appendSolid(mesh, sphere, domain);
    EXPECT_GT(mesh.triangleCount(), 500u);
    for (std::size_t v = 0; v < 3 * mesh.triangleCount(); ++v)
        EXPECT_NEAR(length(mesh.position(v) - sphere.center), sphere.radius, 1e-5f);

    SolidDescription cylinder;
    cylinder.kind = SolidDescription::Kind::Cylinder;
    cylinder.base = {0.5f, 0.1f, 0.5f};
    cylinder.axis = {0.0f, 2.0f, 0.0f};  // normalised inside, as the solver does
    cylinder.radius = 0.1f;
    cylinder.height = 0.3f;
    mesh = {};
    appendSolid(mesh, cylinder, domain);
    int onBase = 0, onTop = 0;
    for (std::size_t v = 0; v < 3 * mesh.triangleCount(); ++v) {
        const Vec3 p = mesh.position(v);
        const float radial = std::hypot(p.x - 0.5f, p.z - 0.5f);
        EXPECT_LE(radial, 0.1f + 1e-5f);
        EXPECT_TRUE(std::abs(p.y - 0.1f) < 1e-5f || std::abs(p.y - 0.4f) < 1e-5f);
        if (radial < 1e-6f) (p.y < 0.2f ? onBase : onTop) += 1;
    }
    EXPECT_GT(onBase, 0);  // both caps are closed
    EXPECT_GT(onTop, 0);

    // A tilted plane is cut to the domain: every corner on the plane and in the box.
    SolidDescription plane;
    plane.kind = SolidDescription::Kind::Plane;
    plane.point = {0.5f, 0.3f, 0.5f};
    plane.normal = {0.2f, 1.0f, 0.1f};
    mesh = {};
    appendSolid(mesh, plane, domain);
    ASSERT_GE(mesh.triangleCount(), 3u);
    float area = 0.0f;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const Vec3 a = mesh.position(3 * t), b = mesh.position(3 * t + 1),
                   c = mesh.position(3 * t + 2);
        area += 0.5f * length(cross(b - a, c - a));
        for (const Vec3& p : {a, b, c}) {
            EXPECT_NEAR(dot(p - plane.point, plane.normal), 0.0f, 1e-5f);
            EXPECT_TRUE(
                Aabb({{-1e-5f, -1e-5f, -1e-5f}, {1.00001f, 1.00001f, 1.00001f}}).contains(p));
        }
    }
    // The cut's area is the domain's cross-section: 1 / |n_y| for this normal.
    EXPECT_NEAR(area, length(plane.normal) / plane.normal.y, 1e-3f);
    // A plane outside the domain draws nothing.
    plane.point = {0.5f, 2.0f, 0.5f};
    plane.normal = {0.0f, 1.0f, 0.0f};
    mesh = {};
    appendSolid(mesh, plane, domain);
    EXPECT_EQ(mesh.triangleCount(), 0u);
}

// The drawn mesh lies on the surface of the solver's solid: same file, same transform.
TEST(SolidMesh, ObjMeshLiesOnTheSolversSurface) {
    const std::string cube = std::string(PBF_SCENES_DIR) + "/../tests/data/cube.obj";
    const Scene scene = parseScene(
        test::smallSceneJson(
            R"("solids": [{"type": "mesh", "file": ")" + cube +
            R"(", "scale": 0.1, "rotation": [0, 30, 10], "translation": [0.2, 0.25, 0.2]}])"),
        "inline.json");
    const SolidMesh mesh = tessellateSolids(scene);
    EXPECT_EQ(mesh.triangleCount(), 12u);
    const auto solids = buildSolids(scene);
    ASSERT_EQ(solids->size(), 1u);
    for (std::size_t v = 0; v < 3 * mesh.triangleCount(); ++v) {
        Vec3 normal;
        // The level set's voxels are a fraction of the particle radius (0.02 m).
        EXPECT_NEAR(solids->signedDistance(mesh.position(v), 1.0f, normal), 0.0f, 0.01f);
    }
    // A missing file names the scene and the field.
    const Scene missing = parseScene(
        test::smallSceneJson(R"("solids": [{"type": "mesh", "file": "/nonexistent/x.obj"}])"),
        "inline.json");
    try {
        (void)tessellateSolids(missing);
        ADD_FAILURE() << "no error for a missing mesh file";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("solids[0].file"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("x.obj"), std::string::npos) << e.what();
    }
}

// A driven mesh is drawn where the World puts it: the drawn vertices lie on
// the solver's surface at the same time (the mesh turning about its pivot),
// and the static solids leave it out.
TEST(SolidMesh, ADrivenSolidIsDrawnWhereTheSolverHasIt) {
    const std::string cube = std::string(PBF_SCENES_DIR) + "/../tests/data/cube.obj";
    const Scene scene =
        parseScene(test::smallSceneJson(
                       R"("solids": [{"type": "mesh", "file": ")" + cube +
                       R"(", "scale": 0.1, "rotation": [0, 30, 0], "translation": [0.2, 0.25, 0.2],
               "motion": {"type": "rotate", "axis": [1, 0, 1], "speed": 600,
                          "pivot": [0.25, 0.25, 0.2]}},
              {"type": "sphere", "center": [0.3, 0.3, 0.3], "radius": 0.02}])"),
                   "inline.json");
    EXPECT_EQ(tessellateSolids(scene).triangleCount(), tessellateSolids([&] {
                                                           Scene only = scene;
                                                           only.solids.erase(only.solids.begin());
                                                           return only;
                                                       }())
                                                           .triangleCount());
    const std::vector<DrivenShape> driven = tessellateDrivenSolids(scene);
    ASSERT_EQ(driven.size(), 1u);
    World world(scene);
    for (int frame = 0; frame < 3; ++frame) test::stepFrame(world);
    SolidMesh mesh;
    appendDriven(mesh, driven, world.time());
    ASSERT_EQ(mesh.triangleCount(), 12u);
    const SolidSet& solids = world.solids();
    for (std::size_t v = 0; v < 3 * mesh.triangleCount(); ++v) {
        Vec3 normal;
        EXPECT_NEAR(solids.signedDistance(mesh.position(v), 1.0f, normal), 0.0f, 0.01f);
    }
    // At rest it was elsewhere: the motion moved it by more than the tolerance.
    SolidMesh rest;
    appendDriven(rest, driven, 0.0);
    EXPECT_GT(length(rest.position(0) - mesh.position(0)), 0.02f);
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
