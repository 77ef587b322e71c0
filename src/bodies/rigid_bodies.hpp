// The rigid bodies of a World (private header): built from the definition,
// their state, and the two halves of a coupled substep.
//
// Coupling (Macklin & Mueller 2013's solver, with the fluid's reaction as the
// body's force; src/backend/reactions.hpp). Each body's surface is a solid of
// the World's SolidSet — the signed-distance boundary pbf already has for
// static solids, moved with the body. Why that and not Akinci et al. 2012's
// boundary samples: the SDF boundary already gives walls and solids the
// rest-lattice density (no gap, no stickiness, flat-wall accurate), a swept
// collision that never lets a particle through, and velocity-relative
// friction; sampling bodies with particles would add a second boundary
// model with its own density error (the cause of floating bodies needing
// the wrong density in SPlisHSPlasH #56 / #378) and cost per surface sample.
// Per substep of length dt:
//   placeForFluid  the bodies' surfaces go where the bodies will be at the
//                  end of the substep (pose + dt velocity), with their
//                  velocities: the fluid's x* (end-of-step positions) meet
//                  the surface there, and friction sees its velocity;
//   (fluid step)   the backend records the reaction of everything the
//                  moving boundaries did to the particles;
//   advance        the reactions (force, torque) act on the bodies with
//                  gravity and the contacts, one Bullet step of dt; the
//                  surfaces go to the new poses.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pbf/backend/backend.hpp"
#include "pbf/bodies/rigid_body.hpp"
#include "pbf/core/errors.hpp"
#include "pbf/core/params.hpp"
#include "pbf/geometry/solid_description.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf::detail {

class ContactWorld;

// What the bodies are built from: the bodies, the static solids they
// collide with, the domain (walls) and particle radius, and the scene's name
// for messages (a WorldDef provides them; the bodies do not know the World).
struct BodiesSetup {
    std::string source;  // "scenes/x.json" (or the world's name), for messages
    const SimulationParams& simulation;
    std::span<const SolidDescription> solids;
    std::span<const RigidBodyDescription> bodies;
};

class RigidBodies {
  public:
    // Adds each body's surface to `solids` (coupled) and builds the contact
    // world. Throws SceneError naming the scene and field for a broken
    // mesh (unreadable, open, no volume) or bodies that overlap each other,
    // a solid or the domain walls at the start.
    RigidBodies(const BodiesSetup& setup, SolidSet& solids);
    ~RigidBodies();

    std::size_t size() const { return infos_.size(); }
    bool empty() const { return infos_.empty(); }
    const std::vector<RigidBodyInfo>& infos() const { return infos_; }
    const std::vector<RigidBodyState>& states() const { return states_; }
    const std::vector<RigidBodyLoad>& loads() const { return loads_; }
    // Replaces a body's state (between frames; the orientation is
    // normalised); its surface follows.
    void setState(std::size_t i, const RigidBodyState& state, SolidSet& solids);
    // Puts a checkpoint's states back, bit for bit.
    void setStates(std::vector<RigidBodyState> states, SolidSet& solids);

    // Largest speed of a body's surface: |v| + |omega| * bounding radius.
    float maxSurfaceSpeed() const;
    // The first body with a non-finite state, or size().
    std::size_t firstBadBody() const;

    // Start of a frame: the contact world rebuilt from the states alone.
    void beginFrame(double frameDuration);
    void placeForFluid(double dt, SolidSet& solids) const;
    void advance(double dt, const Vec3& gravity, std::span<const SolidReaction> reactions,
                 SolidSet& solids);

  private:
    SolidMotion surfaceMotion(std::size_t i, const RigidBodyState& s) const;

    std::vector<RigidBodyInfo> infos_;
    std::vector<RigidBodyState> states_;
    std::vector<RigidBodyLoad> loads_;  // fluid's push averaged over the frame
    std::unique_ptr<ContactWorld> contacts_;
    double frameDuration_ = 0.0;
    std::vector<Vec3> forces_, torques_;  // scratch for advance()
};

}  // namespace pbf::detail
