// The part of a backend whose particles live in host memory (private
// header): the particle store, appending, and the reductions, shared by the
// CPU and reference backends. A device backend implements Backend directly.
#pragma once

#include <vector>

#include "backend/outlets.hpp"
#include "backend/reactions.hpp"
#include "pbf/backend/backend.hpp"

namespace pbf {

class HostBackend : public Backend {
  public:
    std::size_t size() const override { return store_.size(); }
    void append(std::span<const Vec3> positions, std::span<const Vec3> velocities,
                float density) override;
    std::size_t removeInside(std::span<const OutletRegion> outlets) override;
    void driveInside(std::span<const InletBuffer> buffers) override {
        detail::driveInside(store_, buffers);
    }
    const StageTimes& lastStageTimes() const override { return times_; }
    std::span<const SolidReaction> lastReactions() const override { return lastReactions_; }

    float maxSpeed() const override;
    std::optional<BadParticle> findBadParticle(double speedLimit) const override;
    StateStatistics statistics(const SolverContext& context) const override;

    const ParticleStore* hostState() const override { return &store_; }
    ParticleStore* mutableHostState() override { return &store_; }
    void download(ParticleStore& out) const override;
    void upload(ParticleStore state) override {
        checkParticlesPerProcess(kind(), 0, state.size());
        store_ = std::move(state);
    }

  protected:
    ParticleStore store_;
    StageTimes times_;
    ReactionAccumulator reactions_;  // filled by step() when a solid is coupled
    std::vector<SolidReaction> lastReactions_;
};

}  // namespace pbf
