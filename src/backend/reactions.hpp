// The fluid's reaction on coupled solids (rigid bodies), accumulated during
// one solver step without atomics (private header).
//
// Two-way coupling by momentum exchange: whatever the boundary of a coupled
// solid does to a fluid particle of mass m — the boundary term of the
// position correction (lambda_i times the solid's share of grad C_i), the
// projection out of the solid, the restitution / friction response — moves
// the particle's end-of-step position by some d (a velocity change dv counts
// as d = dv dt, since v = (x* - x) / dt), i.e. gives it the impulse m d / dt.
// By Newton's third law the solid receives -m d / dt: the step's force on
// the solid is F = -(m / dt^2) sum d and its torque about the solid frame's
// origin o is -(m / dt^2) sum (x - o) x d. This is how SPlisHSPlasH couples
// PBF to rigid bodies (the boundary correction's reaction, -m dx / dt^2),
// extended to the collision and friction terms so that fluid + bodies
// conserve momentum exactly up to rounding (tests/bodies/bodies_test.cpp).
//
// Determinism: sums are kept per fixed block of detail::kBlockSize particle
// indices (one thread works on a block at a time, in index order) and per
// solid, then added in block order, so 1 and N threads give the same bits.
#pragma once

#include <cstddef>
#include <vector>

#include "backend/boundary.hpp"
#include "core/blocks.hpp"
#include "pbf/backend/backend.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf {

// The reaction of a step from the sums of its moves (d, metres) and their
// moments ((x - o) x d, m^2): F = -(m / dt^2) sum d, torque likewise.
// `sums` = {sum dx, dy, dz, sum mx, my, mz}.
inline SolidReaction reactionFromSums(const double sums[6], float particleMass, float dt) {
    const double scale = -double(particleMass) / (double(dt) * double(dt));
    return {{float(scale * sums[0]), float(scale * sums[1]), float(scale * sums[2])},
            {float(scale * sums[3]), float(scale * sums[4]), float(scale * sums[5])}};
}

class ReactionAccumulator {
  public:
    // Zeroed sums for `particles` particles and the solids of `solids`
    // (null or none coupled: inactive, add() is never to be called).
    void reset(std::size_t particles, const SolidSet* solids) {
        active_ = solids && solids->anyCoupled();
        if (!active_) return;
        solidCount_ = solids->size();
        coupled_.assign(solidCount_, false);
        origins_.resize(solidCount_);
        for (std::size_t k = 0; k < solidCount_; ++k) {
            coupled_[k] = solids->coupled(k);
            origins_[k] = solids->motion(k).pose.position;
        }
        const std::size_t blocks = (particles + detail::kBlockSize - 1) / detail::kBlockSize;
        sums_.assign(blocks * solidCount_, Sum{});
    }
    bool active() const { return active_; }
    // Room for particle indices below `particles`, keeping the sums so far
    // (a distributed step adds migrated particles and ghosts after the
    // swept collision has recorded its moves).
    void grow(std::size_t particles) {
        if (!active_) return;
        const std::size_t blocks = (particles + detail::kBlockSize - 1) / detail::kBlockSize;
        if (blocks * solidCount_ > sums_.size()) sums_.resize(blocks * solidCount_, Sum{});
    }

    // The boundary of solid `solid` moved particle `particle`, at x, by
    // `displacement` (metres; a velocity change dv as dv dt). Only the thread
    // working on the particle's block may call this for it.
    void add(std::size_t particle, std::size_t solid, const Vec3& x, const Vec3& displacement) {
        if (solid >= solidCount_ || !coupled_[solid]) return;
        Sum& s = sums_[(particle / detail::kBlockSize) * solidCount_ + solid];
        const Vec3 moment = cross(x - origins_[solid], displacement);
        s.dx += displacement.x;
        s.dy += displacement.y;
        s.dz += displacement.z;
        s.mx += moment.x;
        s.my += moment.y;
        s.mz += moment.z;
    }

    // The reactions of the step: F = -(m / dt^2) sum d, torque about the
    // solid frame's origin likewise; one entry per solid (zero for solids
    // that are not coupled). Sums in block order: deterministic.
    void forces(float particleMass, float dt, std::vector<SolidReaction>& out) const {
        out.assign(active_ ? solidCount_ : 0, SolidReaction{});
        if (!active_) return;
        for (std::size_t k = 0; k < solidCount_; ++k) {
            Sum total;
            for (std::size_t b = 0; b * solidCount_ < sums_.size(); ++b) {
                const Sum& s = sums_[b * solidCount_ + k];
                total.dx += s.dx;
                total.dy += s.dy;
                total.dz += s.dz;
                total.mx += s.mx;
                total.my += s.my;
                total.mz += s.mz;
            }
            const double sums[6] = {total.dx, total.dy, total.dz, total.mx, total.my, total.mz};
            out[k] = reactionFromSums(sums, particleMass, dt);
        }
    }

  private:
    struct Sum {
        double dx = 0.0, dy = 0.0, dz = 0.0;  // sum of displacements, m
        double mx = 0.0, my = 0.0, mz = 0.0;  // sum of (x - o) x d, m^2
    };
    bool active_ = false;
    std::size_t solidCount_ = 0;
    std::vector<bool> coupled_;
    std::vector<Vec3> origins_;
    std::vector<Sum> sums_;  // [block][solid]
};

}  // namespace pbf
