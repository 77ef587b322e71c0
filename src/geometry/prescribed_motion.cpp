#include "pbf/geometry/prescribed_motion.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace pbf {
namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

Vec3 unit(const Vec3& v) {
    return v * (1.0f / length(v));
}

Quat normalisedQuat(const Quat& q) {
    const float n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    return {q.w / n, q.x / n, q.y / n, q.z / n};
}

// The rotation from a to b as an axis and an angle (radians, [0, pi]): the
// shortest arc, q = axisAngle(axis, angle) * a.
void arcBetween(const Quat& a, Quat b, Vec3& axis, double& angle) {
    // q and -q are the same rotation: take the one nearer a.
    if (a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z < 0.0f) b = {-b.w, -b.x, -b.y, -b.z};
    const Quat r = b * a.conjugate();
    const double s = std::sqrt(double(r.x) * r.x + double(r.y) * r.y + double(r.z) * r.z);
    angle = 2.0 * std::atan2(s, double(r.w));
    axis = s > 0.0 ? Vec3{float(r.x / s), float(r.y / s), float(r.z / s)} : Vec3{0, 1, 0};
}

Displacement keyframesAt(const std::vector<MotionKey>& keys, double t) {
    Displacement d;
    if (keys.empty()) return d;
    if (t <= keys.front().time) {
        d.translation = keys.front().position;
        d.rotation = fromEulerDegrees(keys.front().rotationDegrees);
        return d;
    }
    if (t >= keys.back().time) {
        d.translation = keys.back().position;
        d.rotation = fromEulerDegrees(keys.back().rotationDegrees);
        return d;
    }
    // The segment [k0, k1] holding t (keys are in increasing time).
    const auto next = std::upper_bound(
        keys.begin(), keys.end(), t, [](double time, const MotionKey& k) { return time < k.time; });
    const MotionKey& k1 = *next;
    const MotionKey& k0 = *(next - 1);
    const double span = k1.time - k0.time;
    const double s = (t - k0.time) / span;
    d.translation = k0.position + (k1.position - k0.position) * float(s);
    d.velocity = (k1.position - k0.position) * float(1.0 / span);
    const Quat q0 = fromEulerDegrees(k0.rotationDegrees);
    Vec3 axis;
    double angle = 0.0;
    arcBetween(q0, fromEulerDegrees(k1.rotationDegrees), axis, angle);
    d.rotation = normalisedQuat(axisAngle(axis, float(s * angle)) * q0);
    d.angularVelocity = axis * float(angle / span);
    return d;
}

// The wave makers' ramp: 0 at t = 0 rising to 1 at t = ramp, smoothly (half
// a cosine), and its rate.
void ramp(double t, double seconds, double& r, double& rate) {
    if (seconds <= 0.0 || t >= seconds) {
        r = 1.0;
        rate = 0.0;
        return;
    }
    if (t <= 0.0) {
        r = rate = 0.0;
        return;
    }
    r = 0.5 * (1.0 - std::cos(std::numbers::pi * t / seconds));
    rate = 0.5 * std::numbers::pi / seconds * std::sin(std::numbers::pi * t / seconds);
}

constexpr double kGravity = 9.81;  // the wave makers' theory: g of Earth, as the scenes'

Vec3 horizontalUnit(const Vec3& v) {
    return unit(Vec3{v.x, 0.0f, v.z});
}

}  // namespace

double waveNumber(double period, double depth, double gravity) {
    const double omega2 = std::pow(2.0 * std::numbers::pi / period, 2.0);
    // Newton on f(k) = g k tanh(k h) - omega^2 from the larger of the deep-
    // and shallow-water answers (f is increasing and convex there).
    double k = std::max(omega2 / gravity, std::sqrt(omega2 / (gravity * depth)));
    for (int i = 0; i < 50; ++i) {
        const double th = std::tanh(k * depth);
        const double f = gravity * k * th - omega2;
        const double df = gravity * (th + k * depth * (1.0 - th * th));
        const double step = f / df;
        k -= step;
        if (std::fabs(step) < 1e-14 * k) break;
    }
    return k;
}

WaveMaker waveMakerOf(const PrescribedMotion& m) {
    WaveMaker w;
    const double h = m.depth;
    w.waveNumber = waveNumber(m.period, h, kGravity);
    w.wavelength = 2.0 * std::numbers::pi / w.waveNumber;
    const double kh = w.waveNumber * h;
    const double denominator = std::sinh(2.0 * kh) + 2.0 * kh;
    w.heightPerStroke =
        m.kind == PrescribedMotion::Kind::Flap
            ? 4.0 * std::sinh(kh) / kh * (kh * std::sinh(kh) - std::cosh(kh) + 1.0) / denominator
            : 2.0 * (std::cosh(2.0 * kh) - 1.0) / denominator;
    w.stroke = m.waveHeight / w.heightPerStroke;
    w.rampSeconds = m.ramp < 0.0f ? 2.0 * m.period : double(m.ramp);
    return w;
}

std::string describe(const PrescribedMotion& m) {
    if (m.kind != PrescribedMotion::Kind::Piston && m.kind != PrescribedMotion::Kind::Flap)
        return {};
    const WaveMaker w = waveMakerOf(m);
    const bool flap = m.kind == PrescribedMotion::Kind::Flap;
    return fmt::format(
        "{} wave maker: waves {} m high, {} s, in {} m of water: wavelength {:.4g} m (k h = "
        "{:.3g}), H / S = {:.4g}, stroke {:.4g} m{} (amplitude {:.4g} m at the still-water "
        "level), ramp {:.3g} s",
        flap ? "flap" : "piston", m.waveHeight, m.period, m.depth, w.wavelength,
        w.waveNumber * m.depth, w.heightPerStroke, w.stroke,
        flap ? fmt::format(", {:.3g} degrees each way",
                           std::atan(0.5 * w.stroke / m.depth) * 180.0 / std::numbers::pi)
             : std::string(),
        0.5 * w.stroke, w.rampSeconds);
}

Displacement displacementAt(const PrescribedMotion& m, double t) {
    Displacement d;
    switch (m.kind) {
        case PrescribedMotion::Kind::None:
            break;
        case PrescribedMotion::Kind::Oscillate: {
            const double omega = 2.0 * std::numbers::pi / m.period;
            const double phase = omega * t + m.phaseDegrees * kRadiansPerDegree;
            const double sine = std::sin(phase), cosine = std::cos(phase);
            d.translation = m.amplitude * float(sine);
            d.velocity = m.amplitude * float(omega * cosine);
            const Vec3 axis = unit(m.axis);
            const double amplitude = m.angleAmplitude * kRadiansPerDegree;
            d.rotation = axisAngle(axis, float(amplitude * sine));
            d.angularVelocity = axis * float(amplitude * omega * cosine);
            break;
        }
        case PrescribedMotion::Kind::Rotate: {
            const Vec3 axis = unit(m.axis);
            const double speed = m.speedDegrees * kRadiansPerDegree;
            // The angle modulo a turn keeps its float exact over long runs.
            const double angle = std::fmod(speed * t, 2.0 * std::numbers::pi);
            d.rotation = axisAngle(axis, float(angle));
            d.angularVelocity = axis * float(speed);
            break;
        }
        case PrescribedMotion::Kind::Keyframes:
            d = keyframesAt(m.keys, t);
            break;
        case PrescribedMotion::Kind::Piston:
        case PrescribedMotion::Kind::Flap: {
            const WaveMaker w = waveMakerOf(m);
            const double omega = 2.0 * std::numbers::pi / m.period;
            double r = 0.0, rate = 0.0;
            ramp(t, w.rampSeconds, r, rate);
            // s(t) = r(t) sin(omega t): the paddle's excursion in units of
            // its amplitude, and its rate.
            const double s = r * std::sin(omega * t);
            const double ds = rate * std::sin(omega * t) + r * omega * std::cos(omega * t);
            const Vec3 direction = horizontalUnit(m.direction);
            if (m.kind == PrescribedMotion::Kind::Piston) {
                d.translation = direction * float(0.5 * w.stroke * s);
                d.velocity = direction * float(0.5 * w.stroke * ds);
            } else {
                // A turn about the hinge that moves the paddle's face at the
                // still-water level by S / 2 along `direction`.
                const Vec3 hinge = cross(Vec3{0, 1, 0}, direction);
                const double amplitude = std::atan(0.5 * w.stroke / m.depth);
                d.rotation = axisAngle(hinge, float(amplitude * s));
                d.angularVelocity = hinge * float(amplitude * ds);
            }
            break;
        }
    }
    return d;
}

SolidMotion motionAt(const PrescribedMotion& m, const Pose& rest, const Vec3& pivot, double t) {
    if (!m.moves()) return {rest, {}, {}};
    const Displacement d = displacementAt(m, t);
    // x = c + d + R (x0 - c) for every point x0 of the solid at rest.
    SolidMotion motion;
    motion.pose.orientation = normalisedQuat(d.rotation * rest.orientation);
    const Vec3 centre = pivot + d.translation;
    motion.pose.position = centre + rotate(d.rotation, rest.position - pivot);
    motion.velocity = d.velocity + cross(d.angularVelocity, motion.pose.position - centre);
    motion.angularVelocity = d.angularVelocity;
    return motion;
}

std::string validate(const PrescribedMotion& m, const std::string& field) {
    const auto finite = [](const Vec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    if (m.hasPivot && !finite(m.pivot)) return field + ".pivot: must be finite";
    switch (m.kind) {
        case PrescribedMotion::Kind::None:
            return {};
        case PrescribedMotion::Kind::Oscillate:
            if (!(m.period > 0.0f) || !std::isfinite(m.period))
                return fmt::format("{}.period: must be positive (s), got {}", field, m.period);
            if (!finite(m.amplitude)) return field + ".amplitude: must be finite";
            if (!std::isfinite(m.angleAmplitude) || std::fabs(m.angleAmplitude) > 180.0f)
                return field + ".angle_amplitude: must be in [-180, 180] degrees";
            if (!std::isfinite(m.phaseDegrees)) return field + ".phase: must be finite";
            if (m.amplitude == Vec3{} && m.angleAmplitude == 0.0f)
                return field +
                       ": an oscillation needs an amplitude (m) or an angle_amplitude (degrees)";
            if (m.angleAmplitude != 0.0f && (!finite(m.axis) || !(length(m.axis) > 0.0f)))
                return field + ".axis: must be a non-zero vector";
            return {};
        case PrescribedMotion::Kind::Rotate:
            if (!finite(m.axis) || !(length(m.axis) > 0.0f))
                return field + ".axis: must be a non-zero vector";
            if (!std::isfinite(m.speedDegrees) || m.speedDegrees == 0.0f)
                return field + ".speed: must be a non-zero angular speed (degrees per second)";
            return {};
        case PrescribedMotion::Kind::Piston:
        case PrescribedMotion::Kind::Flap: {
            if (!(m.period > 0.0f) || !std::isfinite(m.period))
                return fmt::format("{}.period: must be positive (s), got {}", field, m.period);
            if (!(m.depth > 0.0f) || !std::isfinite(m.depth))
                return fmt::format(
                    "{}.depth: must be positive (m, the still water at the "
                    "paddle), got {}",
                    field, m.depth);
            if (!(m.waveHeight > 0.0f) || !std::isfinite(m.waveHeight))
                return fmt::format("{}.wave_height: must be positive (m), got {}", field,
                                   m.waveHeight);
            if (!finite(m.direction) || !(std::fabs(m.direction.x) + std::fabs(m.direction.z) > 0))
                return field + ".direction: must have a horizontal part (x or z)";
            if (!std::isfinite(m.ramp)) return field + ".ramp: must be finite";
            if (m.kind == PrescribedMotion::Kind::Flap && !m.hasPivot)
                return field +
                       ".pivot: a flap turns about its hinge: give the hinge's position "
                       "(on the floor, below the paddle)";
            const WaveMaker w = waveMakerOf(m);
            const double kh = w.waveNumber * m.depth;
            // Miche's limit: steeper waves break.
            const double breaking = 0.142 * w.wavelength * std::tanh(kh);
            if (m.waveHeight > breaking)
                return fmt::format(
                    "{}.wave_height: {} m waves of {} s break in {} m of water (wavelength "
                    "{:.3g} m; Miche's limit 0.142 L tanh(k h) = {:.3g} m)",
                    field, m.waveHeight, m.period, m.depth, w.wavelength, breaking);
            if (0.5 * w.stroke > m.depth)
                return fmt::format(
                    "{}.wave_height: {} m waves of {} s in {} m of water need a stroke of "
                    "{:.3g} m, more than twice the depth: beyond first-order wave-maker theory "
                    "(lower the height or the period, or deepen the water)",
                    field, m.waveHeight, m.period, m.depth, w.stroke);
            return {};
        }
        case PrescribedMotion::Kind::Keyframes: {
            const std::string where = m.source.empty() ? field + ".keys" : m.source;
            if (m.keys.size() < 2)
                return where + ": at least two keyframes are needed (time, position, rotation)";
            for (std::size_t k = 0; k < m.keys.size(); ++k) {
                const MotionKey& key = m.keys[k];
                if (!std::isfinite(key.time) || !finite(key.position) ||
                    !finite(key.rotationDegrees))
                    return fmt::format("{}[{}]: must be finite", where, k);
                if (k > 0 && !(key.time > m.keys[k - 1].time))
                    return fmt::format(
                        "{}[{}].time: keyframes must be in increasing time ({} s after {} s)",
                        where, k, key.time, m.keys[k - 1].time);
            }
            return {};
        }
    }
    return {};
}

}  // namespace pbf
