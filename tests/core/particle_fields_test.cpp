// The particle-field list reaches everything that handles every field.
//
// This file is built into its own executable with two fields added to the
// list (tests/CMakeLists.txt, PBF_EXTRA_PARTICLE_FIELDS): `testVector`, a
// saved 3-vector, and `testTag`, an optional integer. Together with the
// store, the checkpoint's particle arrays and the MPI records — compiled for
// this executable from the same sources as libpbf — the tests show that a
// field listed once is resized, permuted, cut, copied, checkpointed and
// carried between ranks with no other change. A hand-written list anywhere
// in those sources (the bug this list replaced: `reserve` forgot the warm
// start's field) would leave the added fields behind and fail here.
#include <gtest/gtest.h>

#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "backend/mpi/particle_record.hpp"
#include "io/binary_stream.hpp"
#include "io/checkpoint_particles.hpp"
#include "pbf/core/particles.hpp"

#ifndef PBF_TEST_EXTRA_FIELDS
#error "built with the extra fields only (tests/CMakeLists.txt: pbf_particle_fields_tests)"
#endif

namespace {

using pbf::ParticleStore;
using pbf::Vec3;

// Particle i's value in field f, component c: distinct everywhere.
float valueOf(std::size_t field, std::size_t i, std::size_t c) {
    return float(1000 * field + 10 * i + c) + 0.25f;
}

// A store of n particles with every field (the optional ones switched on)
// holding valueOf.
ParticleStore filledStore(std::size_t n) {
    ParticleStore p;
    for (std::size_t i = 0; i < n; ++i) p.add({}, {}, 1000.0f);
    p.keepOptionalFields(~0u);
    std::size_t f = 0;
    p.forEachField([&](const pbf::ParticleFieldInfo&, auto& a) {
        const auto components = pbf::componentsOf(a);
        for (std::size_t c = 0; c < components.size(); ++c)
            for (std::size_t i = 0; i < n; ++i) {
                using T = typename std::remove_reference_t<decltype(*components[c])>::value_type;
                (*components[c])[i] = T(valueOf(f, i, c));
            }
        ++f;
    });
    return p;
}

// Whether particle k of `p` holds the values of particle i of filledStore,
// in every field.
bool holdsParticle(const ParticleStore& p, std::size_t k, std::size_t i) {
    bool same = true;
    std::size_t f = 0;
    p.forEachField([&](const pbf::ParticleFieldInfo&, const auto& a) {
        const auto components = pbf::componentsOf(a);
        for (std::size_t c = 0; c < components.size(); ++c) {
            using T = typename std::remove_cv_t<
                std::remove_reference_t<decltype(*components[c])>>::value_type;
            same = same && k < components[c]->size() && (*components[c])[k] == T(valueOf(f, i, c));
        }
        ++f;
    });
    return same;
}

TEST(ParticleFields, TheAddedFieldsAreInTheListAndTheStore) {
    const auto fields = ParticleStore::fields();
    ASSERT_GE(fields.size(), 2u);
    EXPECT_EQ(std::string(fields[fields.size() - 2].name), "testVector");
    EXPECT_EQ(fields[fields.size() - 2].components, 3);
    EXPECT_EQ(std::string(fields.back().name), "testTag");
    EXPECT_EQ(fields.back().kind, pbf::ParticleFieldKind::Optional);
    ParticleStore p;
    p.add({1, 2, 3}, {}, 1000.0f);
    EXPECT_EQ(p.testVector.size(), 1u);  // a saved field grows with add()
    EXPECT_TRUE(p.testTag.empty());      // an optional field stays off
    p.keepOptionalFields(p.keptOptionalFields() | (1u << (fields.size() - 1)));
    EXPECT_EQ(p.testTag.size(), 1u);
}

TEST(ParticleFields, ReorderPermutesEveryField) {
    const std::size_t n = 7;
    ParticleStore p = filledStore(n);
    const std::vector<std::uint32_t> perm = {3, 0, 6, 1, 5, 2, 4};
    p.reorder(perm);
    for (std::size_t k = 0; k < n; ++k) EXPECT_TRUE(holdsParticle(p, k, perm[k])) << k;
}

// The same through memory the caller lends for the integer fields (the CPU
// solver lends its idle position records), and with a loan too small (the
// store's own scratch).
TEST(ParticleFields, ReorderThroughLentScratchPermutesEveryField) {
    const std::size_t n = 7;
    const std::vector<std::uint32_t> perm = {3, 0, 6, 1, 5, 2, 4};
    std::vector<std::uint64_t> lent(n, ~std::uint64_t{0});
    ParticleStore p = filledStore(n);
    p.reorder(perm, std::as_writable_bytes(std::span(lent)));
    for (std::size_t k = 0; k < n; ++k) EXPECT_TRUE(holdsParticle(p, k, perm[k])) << k;
    EXPECT_NE(lent[0], ~std::uint64_t{0});  // the loan was used
    ParticleStore q = filledStore(n);
    q.reorder(perm, std::as_writable_bytes(std::span(lent).first(n / 2)));
    for (std::size_t k = 0; k < n; ++k) EXPECT_TRUE(holdsParticle(q, k, perm[k])) << k;
}

TEST(ParticleFields, KeepRangeResizeAndCopyCoverEveryField) {
    ParticleStore p = filledStore(6);
    p.keepRange(2, 5);
    ASSERT_EQ(p.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) EXPECT_TRUE(holdsParticle(p, k, k + 2)) << k;

    const ParticleStore source = filledStore(4);
    ParticleStore copy;
    copy.keepOptionalFields(source.keptOptionalFields());
    copy.resize(2);
    copy.copyParticle(0, source, 3);
    copy.copyParticle(1, source, 1);
    EXPECT_TRUE(holdsParticle(copy, 0, 3));
    EXPECT_TRUE(holdsParticle(copy, 1, 1));
    p.reserve(100);
    EXPECT_GE(p.testVector.x.capacity(), 100u);
    EXPECT_GE(p.testTag.capacity(), 100u);
}

TEST(ParticleFields, CheckpointArraysCarryEveryField) {
    const ParticleStore saved = filledStore(5);
    pbf::detail::BinaryWriter w;
    pbf::detail::writeParticleArrays(w, saved);
    const std::string name = "test.pbfck";
    pbf::detail::BinaryReader r(w.bytes(), name);
    ParticleStore restored;
    pbf::detail::readParticleArrays(r, restored);
    EXPECT_TRUE(r.atEnd());
    for (std::size_t i = 0; i < 5; ++i) {
        // The working copy (predicted) is not saved; every other field is.
        restored.predicted = saved.predicted;
        EXPECT_TRUE(holdsParticle(restored, i, i)) << i;
    }
    // 4 bytes per component of every saved or optional field, 8 for the id.
    std::size_t bytes = 4;
    for (const auto& f : ParticleStore::fields())
        if (f.kind != pbf::ParticleFieldKind::Working) bytes += 4 * std::size_t(f.components);
    EXPECT_EQ(pbf::detail::savedBytesPerParticle(), bytes);
}

TEST(ParticleFields, MpiRecordsCarryEveryField) {
    const ParticleStore source = filledStore(3);
    ParticleStore arrived;
    arrived.keepOptionalFields(source.keptOptionalFields());
    arrived.resize(3);
    for (std::size_t i = 0; i < 3; ++i)
        pbf::setFromRecord(arrived, 2 - i, pbf::recordOf(source, i, /*key=*/i));
    for (std::size_t i = 0; i < 3; ++i) EXPECT_TRUE(holdsParticle(arrived, 2 - i, i)) << i;
    EXPECT_EQ(pbf::recordOf(source, 1, 42).key, 42u);
}

}  // namespace

#if defined(PBF_HAVE_DEVICE_FIELDS_TEST)
#include "pbf/backend/backend.hpp"
#include "pbf/core/solver_constants.hpp"

namespace pbf::gpu::on_cpu_fields_test {
std::unique_ptr<pbf::Backend> makeBackend(const pbf::SimulationParams& params);
}

namespace {

// Every array of every field, as doubles, in list order.
std::vector<std::vector<double>> allArrays(const ParticleStore& p) {
    std::vector<std::vector<double>> arrays;
    p.forEachField([&](const pbf::ParticleFieldInfo&, const auto& a) {
        for (const auto* c : pbf::componentsOf(a)) arrays.emplace_back(c->begin(), c->end());
    });
    return arrays;
}

}  // namespace

// The GPU backend's device arrays (tests/core/particle_fields_device.cpp):
// upload and download carry every field, append extends every field, and a
// step's reorder by cell permutes every field with the particle.
TEST(ParticleFields, DeviceArraysCarryEveryField) {
    const std::size_t n = 500;
    ParticleStore p = filledStore(n);
    for (std::size_t i = 0; i < n; ++i) {  // a cloud in the domain, so the step sorts it
        const float t = float(i);
        p.position.set(i, {0.1f + 0.0017f * float((i * 37) % 400), 0.2f + 0.0011f * t,
                           0.3f + 0.0013f * float((i * 53) % 300)});
        p.predicted.set(i, p.position.get(i));
        p.id[i] = std::uint32_t(i);
    }
    p.setNextId(std::uint32_t(n));
    pbf::SimulationParams params;
    params.domain = {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};
    params.particleRadius = 0.01f;
    const pbf::SolverConstants constants = pbf::SolverConstants::from(params);
    std::unique_ptr<pbf::Backend> device = pbf::gpu::on_cpu_fields_test::makeBackend(params);
    device->upload(p);
    ParticleStore back;
    device->download(back);
    EXPECT_EQ(allArrays(back), allArrays(p));
    EXPECT_EQ(back.keptOptionalFields(), p.keptOptionalFields());

    const std::vector<Vec3> added(3, Vec3{0.5f, 0.5f, 0.5f});
    device->append(added, added, 1000.0f);
    device->step({params, constants, nullptr}, 0.001f);
    device->download(back);
    ASSERT_EQ(back.size(), n + 3);
    std::vector<bool> seen(n + 3, false);
    for (std::size_t k = 0; k < back.size(); ++k) {
        const std::uint64_t i = back.id[k];
        ASSERT_LT(i, n + 3);
        seen[i] = true;
        // The fields the step does not write followed their particle;
        // appended particles got zeros.
        const std::size_t vector = std::size_t(pbf::ParticleField::testVector);
        const std::size_t tag = std::size_t(pbf::ParticleField::testTag);
        const auto components = pbf::componentsOf(back.testVector);
        for (std::size_t c = 0; c < 3; ++c)
            EXPECT_EQ((*components[c])[k], i < n ? valueOf(vector, i, c) : 0.0f)
                << "particle " << i;
        EXPECT_EQ(back.testTag[k], i < n ? std::uint32_t(valueOf(tag, i, 0)) : 0u)
            << "particle " << i;
    }
    for (std::size_t i = 0; i < n + 3; ++i) EXPECT_TRUE(seen[i]) << "id " << i;
    // The step did sort: the memory order changed.
    std::size_t moved = 0;
    for (std::size_t k = 0; k < back.size(); ++k) moved += back.id[k] != k;
    EXPECT_GT(moved, n / 2);
}
#endif
