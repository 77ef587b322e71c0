// The GPU backend's CPU build against the two Thrusts pbf supports: the
// CUDA toolkit's CCCL (the main build) and Debian's Thrust 1.17
// (build_on_cpu_thrust117.cpp, compiled in where both are installed). The
// same source with the same algorithms (stable sort, gathers, integer and
// max reductions, per-block sums) must give the same bits. Catches code
// that compiles against one Thrust only, and an algorithm whose result
// depends on the Thrust version (an unstable sort, a float reduction).
#include <gtest/gtest.h>

#include <cstring>
#include <memory>

#include "backend/gpu/device_backend.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/world/world_def.hpp"
#include "support/drift_check.hpp"

#if defined(PBF_HAVE_THRUST117_BUILD)
namespace pbf::gpu::on_cpu_thrust117 {
std::unique_ptr<Backend> makeBackend(const SimulationParams& params);
int thrustVersion();
}  // namespace pbf::gpu::on_cpu_thrust117
#endif

namespace pbf::test {
namespace {

TEST(DeviceThrustVersions, CcclAndDebianThrustGiveTheSameBits) {
#if !defined(PBF_HAVE_THRUST117_BUILD)
    GTEST_SKIP() << "one Thrust only here: the cuda-on-cpu device is built against "
                 << PBF_THRUST_INCLUDE_DIR_TEXT
                 << "; the check needs the CUDA toolkit's CCCL and Debian's libthrust-dev";
#else
    if (!deviceInfo(BackendKind::CudaOnCpu).usable) GTEST_SKIP() << "no cuda-on-cpu build";
    Scene scene = parseScene(smallDamBreakJson(R"(, "warm_start": 0.8)"), "small_dam_break");
    const SimulationParams& params = scene.simulation;
    const SolverConstants constants = SolverConstants::from(params);
    const std::unique_ptr<SolidSet> solids = buildSolids(scene);
    const SolverContext context{params, constants, solids.get()};
    std::unique_ptr<Backend> cccl = gpu::on_cpu::makeBackend(params, {});
    std::unique_ptr<Backend> debian = gpu::on_cpu_thrust117::makeBackend(params);
    std::printf("  Thrust %d (Debian) against the main build's\n",
                gpu::on_cpu_thrust117::thrustVersion());
    const ParticleStore initial = createParticles(scene, solids.get());
    cccl->upload(initial);
    debian->upload(initial);
    for (int step = 0; step < 40; ++step) {
        cccl->step(context, 1.0f / 300.0f);
        debian->step(context, 1.0f / 300.0f);
    }
    ParticleStore a, b;
    cccl->download(a);
    debian->download(b);
    ASSERT_EQ(a.size(), b.size());
    for (const auto field : {&Float3Array::x, &Float3Array::y, &Float3Array::z}) {
        EXPECT_EQ(std::memcmp((a.position.*field).data(), (b.position.*field).data(),
                              a.size() * sizeof(float)),
                  0);
        EXPECT_EQ(std::memcmp((a.velocity.*field).data(), (b.velocity.*field).data(),
                              a.size() * sizeof(float)),
                  0);
    }
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(cccl->statistics(context).kineticEnergy, debian->statistics(context).kineticEnergy);
    EXPECT_GT(cccl->maxSpeed(), 0.5f);  // the flow moved
#endif
}

}  // namespace
}  // namespace pbf::test
