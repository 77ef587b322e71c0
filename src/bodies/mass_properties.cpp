#include "bodies/mass_properties.hpp"

#include <cmath>
#include <numbers>

namespace pbf::detail {
namespace {

// Inertia tensor of a body from its second moment C = integral of x x^T:
// I = trace(C) Id - C.
Matrix3 inertiaFromSecondMoment(const Matrix3& c) {
    const double trace = c[0][0] + c[1][1] + c[2][2];
    Matrix3 inertia{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) inertia[i][j] = (i == j ? trace : 0.0) - c[i][j];
    return inertia;
}

Matrix3 diagonal(double a, double b, double c) {
    Matrix3 m{};
    m[0][0] = a;
    m[1][1] = b;
    m[2][2] = c;
    return m;
}

// Rotation matrix (columns = rotated axes) to a unit quaternion (Shepperd's method).
Quat toQuaternion(const Matrix3& m) {
    const double trace = m[0][0] + m[1][1] + m[2][2];
    double w, x, y, z;
    if (trace > 0.0) {
        const double s = 2.0 * std::sqrt(trace + 1.0);
        w = 0.25 * s;
        x = (m[2][1] - m[1][2]) / s;
        y = (m[0][2] - m[2][0]) / s;
        z = (m[1][0] - m[0][1]) / s;
    } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
        const double s = 2.0 * std::sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]);
        w = (m[2][1] - m[1][2]) / s;
        x = 0.25 * s;
        y = (m[0][1] + m[1][0]) / s;
        z = (m[0][2] + m[2][0]) / s;
    } else if (m[1][1] > m[2][2]) {
        const double s = 2.0 * std::sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]);
        w = (m[0][2] - m[2][0]) / s;
        x = (m[0][1] + m[1][0]) / s;
        y = 0.25 * s;
        z = (m[1][2] + m[2][1]) / s;
    } else {
        const double s = 2.0 * std::sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]);
        w = (m[1][0] - m[0][1]) / s;
        x = (m[0][2] + m[2][0]) / s;
        y = (m[1][2] + m[2][1]) / s;
        z = 0.25 * s;
    }
    const double n = std::sqrt(w * w + x * x + y * y + z * z);
    return {float(w / n), float(x / n), float(y / n), float(z / n)};
}

}  // namespace

MassProperties boxMassProperties(const Vec3& h) {
    MassProperties p;
    const double a = 2.0 * h.x, b = 2.0 * h.y, c = 2.0 * h.z;
    p.volume = a * b * c;
    p.inertia = diagonal(p.volume * (b * b + c * c) / 12.0, p.volume * (a * a + c * c) / 12.0,
                         p.volume * (a * a + b * b) / 12.0);
    return p;
}

MassProperties sphereMassProperties(float radius) {
    MassProperties p;
    const double r = radius;
    p.volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    const double moment = 0.4 * p.volume * r * r;
    p.inertia = diagonal(moment, moment, moment);
    return p;
}

MassProperties cylinderMassProperties(float radius, float height) {
    MassProperties p;
    const double r = radius, h = height;
    p.volume = std::numbers::pi * r * r * h;
    const double side = p.volume * (3.0 * r * r + h * h) / 12.0;
    p.inertia = diagonal(side, 0.5 * p.volume * r * r, side);
    return p;
}

MassProperties meshMassProperties(std::span<const Vec3> vertices,
                                  std::span<const std::array<std::uint32_t, 3>> triangles) {
    // Each triangle (a, b, c) and the origin span a tetrahedron of signed
    // volume det(a, b, c) / 6; over a closed surface the signed volumes add
    // up to the enclosed volume whatever the origin. Its first moment is
    // V (a + b + c) / 4, its second moment V/20 (a a^T + b b^T + c c^T + s s^T)
    // with s = a + b + c (the origin contributes zero).
    double volume = 0.0;
    std::array<double, 3> first{};
    Matrix3 second{};
    for (const auto& t : triangles) {
        const Vec3& pa = vertices[t[0]];
        const Vec3& pb = vertices[t[1]];
        const Vec3& pc = vertices[t[2]];
        const double a[3] = {pa.x, pa.y, pa.z}, b[3] = {pb.x, pb.y, pb.z},
                     c[3] = {pc.x, pc.y, pc.z};
        const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                           a[2] * (b[0] * c[1] - b[1] * c[0]);
        const double v = det / 6.0;
        volume += v;
        double s[3];
        for (int i = 0; i < 3; ++i) {
            s[i] = a[i] + b[i] + c[i];
            first[i] += v * s[i] / 4.0;
        }
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                second[i][j] += v / 20.0 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
    }
    if (volume < 0.0) {  // inward-facing triangles: every signed integral flips
        volume = -volume;
        for (int i = 0; i < 3; ++i) {
            first[i] = -first[i];
            for (int j = 0; j < 3; ++j) second[i][j] = -second[i][j];
        }
    }
    MassProperties p;
    p.volume = volume;
    if (!(volume > 0.0)) return p;
    for (int i = 0; i < 3; ++i) p.centre[i] = first[i] / volume;
    // Parallel axis: the second moment about the centre.
    Matrix3 central{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            central[i][j] = second[i][j] - volume * p.centre[i] * p.centre[j];
    p.inertia = inertiaFromSecondMoment(central);
    return p;
}

void principalAxes(const Matrix3& inertia, Quat& rotation, Vec3& moments) {
    // Cyclic Jacobi: rotate away the largest off-diagonal entries until the
    // matrix is diagonal; the product of the rotations holds the eigenvectors.
    Matrix3 a = inertia;
    Matrix3 v = diagonal(1.0, 1.0, 1.0);
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30 * scale || off == 0.0) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0.0 ? 1.0 : -1.0) /
                                 (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {  // a = J^T a J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {  // v = v J
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    // A right-handed frame: flip the third axis if the eigenvectors are a reflection.
    const double det = v[0][0] * (v[1][1] * v[2][2] - v[1][2] * v[2][1]) -
                       v[0][1] * (v[1][0] * v[2][2] - v[1][2] * v[2][0]) +
                       v[0][2] * (v[1][0] * v[2][1] - v[1][1] * v[2][0]);
    if (det < 0.0)
        for (int k = 0; k < 3; ++k) v[k][2] = -v[k][2];
    rotation = toQuaternion(v);
    moments = {float(a[0][0]), float(a[1][1]), float(a[2][2])};
}

}  // namespace pbf::detail
