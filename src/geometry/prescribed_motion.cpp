#include "pbf/geometry/prescribed_motion.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

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

}  // namespace

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
