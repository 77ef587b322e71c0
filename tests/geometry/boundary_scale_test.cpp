// The boundary term of a finite body (src/geometry/boundary_scale.hpp) against
// what it stands for: the rest lattice continued into the body. Around a
// 10 cm cube whose faces lie midway between lattice layers, every lattice
// site outside the cube within reach gets the flat-wall density scaled by
// the density map; the exact answer is the kernel sum over the lattice sites
// inside the cube. This is the check that found the density map's
// quadrature tie (at r = 5 mm the ratio at the centre of a face
// was 0.57 instead of 1: mean density error -3 %, worst -8 % on the faces).
#include "geometry/boundary_scale.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "backend/boundary.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf {
namespace {

struct LatticeError {
    double meanFace = 0.0, worst = 0.0;  // relative to the rest lattice's density
    double centreRatio = 0.0;            // the map at the centre of a face, r from it
};

LatticeError compareWithLattice(float r) {
    SimulationParams sim;
    sim.particleRadius = r;
    sim.domain = {{-1, -1, -1}, {1, 1, 1}};
    const SolverConstants c = SolverConstants::from(sim);
    const float half = 0.05f;
    const Aabb cube{{-half, -half, -half}, {half, half, half}};
    SolidSet solids;
    solids.add(makeBoxSolid(cube), {}, /*coupled=*/true);
    const auto scale = std::make_shared<BoundaryScale>(*makeBoxSolid(cube), c.h, c.wall.range, r);
    solids.setBoundaryScale(0, scale);
    // Lattice sites at half + r + 2 r k: the faces lie midway between layers.
    const float s = 2.0f * r;
    const float offset = half + r - s * float(std::lround((half + r) / s));
    const int n = int(std::ceil((half + c.h) / s)) + 1;
    const auto site = [&](int k) { return float(k) * s + offset; };
    const auto inside = [&](const Vec3& y) {
        return std::fabs(y.x) < half && std::fabs(y.y) < half && std::fabs(y.z) < half;
    };
    const double lattice = double(c.restDensity) / double(c.particleMass);  // full kernel sum
    LatticeError e;
    int faces = 0;
    for (int i = -n; i <= n; ++i)
        for (int j = -n; j <= n; ++j)
            for (int k = -n; k <= n; ++k) {
                const Vec3 x{site(i), site(j), site(k)};
                if (inside(x)) continue;
                double missing = 0.0;
                for (int a = -n; a <= n; ++a)
                    for (int b = -n; b <= n; ++b)
                        for (int d = -n; d <= n; ++d) {
                            const Vec3 y{site(a), site(b), site(d)};
                            if (inside(y)) missing += c.poly6.value(lengthSquared(x - y));
                        }
                const boundary::SolidContribution bc = boundary::solidContribution(c, solids, x);
                const double error = (double(bc.kernelSum) - missing) / lattice;
                e.worst = std::max(e.worst, std::fabs(error));
                const int outside =
                    (std::fabs(x.x) > half) + (std::fabs(x.y) > half) + (std::fabs(x.z) > half);
                if (outside == 1 && missing > 0.0) {
                    e.meanFace += error;
                    ++faces;
                }
            }
    e.meanFace /= std::max(1, faces);
    e.centreRatio = scale->at({0.0f, half + r, 0.0f});
    return e;
}

TEST(BoundaryScale, CubeBoundaryMatchesTheLatticeInsideItAtEveryResolution) {
    for (const float r : {0.01f, 0.005f, 0.0025f}) {
        const LatticeError e = compareWithLattice(r);
        std::printf("  r = %g mm: face mean %.4f, worst %.4f, ratio at a face centre %.4f\n",
                    1e3 * r, e.meanFace, e.worst, e.centreRatio);
        EXPECT_NEAR(e.centreRatio, 1.0, 1e-3) << "r = " << r;
        EXPECT_LT(std::fabs(e.meanFace), 0.006) << "r = " << r;
        EXPECT_LT(e.worst, 0.015) << "r = " << r;
    }
}

}  // namespace
}  // namespace pbf
