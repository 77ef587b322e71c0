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
        Oscillate,  // d = amplitude sin(phi), angle = angle_amplitude sin(phi) about axis,
                    // phi = 2 pi t / period + phase
        Rotate,     // a constant angular speed about axis
        Keyframes,  // linear between keys, rotations along the shortest arc; held before the
                    // first and after the last
        Piston,     // wave maker: a translation along `direction` (waveMakerOf)
        Flap,       // wave maker: a turn about the horizontal hinge at `pivot` (the floor)
    };
    Kind kind = Kind::None;
    Vec3 amplitude;               // m (oscillate)
    float angleAmplitude = 0.0f;  // degrees (oscillate)
    float period = 1.0f;          // s (oscillate, piston, flap), > 0
    float phaseDegrees = 0.0f;    // degrees (oscillate)
    Vec3 axis{0, 1, 0};           // rotation axis (oscillate, rotate), normalised on use
    float speedDegrees = 0.0f;    // degrees per second (rotate)
    bool hasPivot = false;        // false: the solid's own centre (pivotOf)
    Vec3 pivot;                   // m, world
    std::vector<MotionKey> keys;  // keyframes, times increasing
    std::string source;           // keyframes read from this CSV file (for messages); may be empty
    // Wave makers (piston, flap): the waves to make, of `waveHeight` and
    // `period`, in still water `depth` deep at the paddle, running along
    // `direction` (horizontal); the paddle's amplitude rises smoothly over
    // `ramp` seconds.
    float waveHeight = 0.0f;  // m, crest to trough
    float depth = 0.0f;       // m
    Vec3 direction{1, 0, 0};
    float ramp = -1.0f;  // s; < 0: two periods

    bool moves() const { return kind != Kind::None; }
};

// What a wave maker does (first-order wave-maker theory, Biesel & Suquet
// 1951; Dean & Dalrymple, "Water wave mechanics for engineers and
// scientists", 1991, sec. 6.2): the wave number k of the period in that
// depth (omega^2 = g k tanh(k h)) and the stroke S (the paddle's excursion
// at the still-water level, twice its amplitude) that makes waves of height
// H far from the paddle:
//   piston: H / S = 2 (cosh 2kh - 1) / (sinh 2kh + 2kh)
//   flap:   H / S = 4 sinh(kh) / (kh) (kh sinh kh - cosh kh + 1) / (sinh 2kh + 2kh)
struct WaveMaker {
    double waveNumber = 0.0;       // k, 1/m
    double wavelength = 0.0;       // 2 pi / k, m
    double heightPerStroke = 0.0;  // H / S
    double stroke = 0.0;           // S, m
    double rampSeconds = 0.0;
};
WaveMaker waveMakerOf(const PrescribedMotion& motion);  // kind Piston or Flap
// The wave number of `period` (s) in water `depth` (m) deep, 1/m.
double waveNumber(double period, double depth, double gravity = 9.81);
// One line for the run's log ("piston wave maker: ..."); empty for other motions.
std::string describe(const PrescribedMotion& motion);

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
