// Particle ids are 64-bit in every backend: a run that created more than
// 2^32 particles (emitters over a long run; a run split over many processes)
// keeps unique ids that follow their particles through the sort by cell,
// appends and downloads. Local indices stay 32-bit: a process refuses more
// particles than it can index, by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf/backend/backend.hpp"
#include "pbf/core/solver_constants.hpp"
#include "support/test_util.hpp"

namespace {

using pbf::BackendKind;
using pbf::Vec3;

constexpr std::uint64_t kFirstId = (std::uint64_t{1} << 32) - 40;  // crosses 2^32

class WideIds : public ::testing::TestWithParam<BackendKind> {};

TEST_P(WideIds, IdsPastThirtyTwoBitsFollowTheirParticles) {
    if (!pbf::deviceInfo(GetParam()).usable) GTEST_SKIP() << "backend not usable here";
    pbf::SimulationParams params;
    params.domain = {{0.0f, 0.0f, 0.0f}, {0.4f, 0.4f, 0.4f}};
    params.particleRadius = 0.01f;
    const pbf::SolverConstants constants = pbf::SolverConstants::from(params);
    // A 6 x 6 x 6 block at rest, ids from kFirstId, in reverse id order in
    // memory (the sort by cell moves every one of them).
    pbf::ParticleStore p;
    p.setNextId(kFirstId);
    for (int k = 0; k < 216; ++k)
        p.add({0.05f + 0.02f * float(k % 6), 0.01f + 0.02f * float(k / 6 % 6),
               0.05f + 0.02f * float(k / 36)},
              {}, 1000.0f);
    std::vector<std::uint32_t> reverse(p.size());
    for (std::size_t k = 0; k < reverse.size(); ++k)
        reverse[k] = std::uint32_t(reverse.size() - 1 - k);
    p.reorder(reverse);
    std::map<std::uint64_t, Vec3> start;
    for (std::size_t i = 0; i < p.size(); ++i) start[p.id[i]] = p.position.get(i);

    const std::unique_ptr<pbf::Backend> backend = pbf::makeBackend(GetParam(), params);
    backend->upload(p);
    const std::vector<Vec3> added = {{0.3f, 0.3f, 0.3f}, {0.32f, 0.3f, 0.3f}};
    backend->append(added, std::vector<Vec3>(2), 1000.0f);
    start[kFirstId + 216] = added[0];
    start[kFirstId + 217] = added[1];
    for (int s = 0; s < 3; ++s) backend->step({params, constants, nullptr}, 0.001f);

    pbf::ParticleStore back;
    backend->download(back);
    ASSERT_EQ(back.size(), 218u);
    EXPECT_EQ(back.nextId(), kFirstId + 218);
    std::vector<std::uint64_t> ids = back.id;
    std::sort(ids.begin(), ids.end());
    for (std::size_t k = 0; k < ids.size(); ++k) ASSERT_EQ(ids[k], kFirstId + k) << k;
    // Each id still names its particle: three steps of 1 ms move none by
    // more than a fraction of a spacing.
    for (std::size_t i = 0; i < back.size(); ++i)
        EXPECT_LT(pbf::length(back.position.get(i) - start.at(back.id[i])), 0.005f)
            << "id " << back.id[i];
}

INSTANTIATE_TEST_SUITE_P(Backends, WideIds, pbf::test::everyBackendHere(),
                         pbf::test::backendTestName);

// More particles than 32-bit indices reach are refused by name before any
// memory is asked for.
TEST(WideIds, AProcessRefusesMoreParticlesThanItCanIndex) {
    EXPECT_NO_THROW(
        pbf::checkParticlesPerProcess(BackendKind::Cpu, pbf::kMaxParticlesPerProcess - 2, 2));
    try {
        pbf::checkParticlesPerProcess(BackendKind::CudaOnCpu, pbf::kMaxParticlesPerProcess - 2, 3);
        ADD_FAILURE() << "no error";
    } catch (const std::length_error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("cuda-on-cpu backend holds at most 4294967295"), std::string::npos)
            << message;
        EXPECT_NE(message.find("MPI"), std::string::npos) << message;
    }
}

}  // namespace
