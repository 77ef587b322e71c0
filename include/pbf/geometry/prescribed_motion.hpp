// A solid's prescribed motion (docs/scenes.md, "Moving solids"): where a
// paddle, a stirrer or a shaken wall is at any time, and how fast it moves
// there, so the water feels its velocity (SolidMotion::velocityAt).
//
// The motion displaces the solid from where its definition puts it: a
// translation d(t) and a rotation R(t) about a pivot c, so a point x0 of the
// solid at rest is at c + d(t) + R(t) (x0 - c). It is a pure function of
// time: a checkpoint needs no state for it and every MPI rank agrees.
#pragma once

#include <string>
#include <vector>

#include "pbf/core/vec3.hpp"
#include "pbf/geometry/pose.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf {

// One keyframe: the displacement at `time` (translation, m; rotation, Euler
// degrees about x, then y, then z, as a mesh's `rotation`).
struct MotionKey {
    double time = 0.0;  // s
    Vec3 position;
    Vec3 rotationDegrees;
};

struct PrescribedMotion {
    enum class Kind {
        None,       // static
        Oscillate,  // d = amplitude sin(phi), angle = angle_amplitude sin(phi) about axis, phi = 2
                    // pi t / period + phase
        Rotate,     // a constant angular speed about axis
        Keyframes,  // linear between keys, rotations along the shortest arc; held before the first
                    // and after the last
    };
    Kind kind = Kind::None;
    Vec3 amplitude;               // m (oscillate)
    float angleAmplitude = 0.0f;  // degrees (oscillate)
    float period = 1.0f;          // s (oscillate), > 0
    float phaseDegrees = 0.0f;    // degrees (oscillate)
    Vec3 axis{0, 1, 0};           // rotation axis (oscillate, rotate), normalised on use
    float speedDegrees = 0.0f;    // degrees per second (rotate)
    bool hasPivot = false;        // false: the solid's own centre (pivotOf)
    Vec3 pivot;                   // m, world
    std::vector<MotionKey> keys;  // keyframes, times increasing
    std::string source;           // keyframes read from this CSV file (for messages); may be empty

    bool moves() const { return kind != Kind::None; }
};

// The displacement at time t and its rates: the velocity of the displaced
// pivot and the angular velocity (world axes).
struct Displacement {
    Vec3 translation;
    Quat rotation;
    Vec3 velocity;         // m/s: d'(t)
    Vec3 angularVelocity;  // rad/s
};
Displacement displacementAt(const PrescribedMotion& motion, double t);

// The solid's pose and velocity at time t: `rest` is its pose at rest (the
// identity for analytic shapes, a mesh's transform), `pivot` the rotations'
// centre.
SolidMotion motionAt(const PrescribedMotion& motion, const Pose& rest, const Vec3& pivot, double t);

// Empty when valid, else "field.key: problem" (`field`: "solids[2].motion").
std::string validate(const PrescribedMotion& motion, const std::string& field);

}  // namespace pbf
