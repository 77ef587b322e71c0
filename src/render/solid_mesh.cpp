// Triangles of the scene's solids for drawing (see solid_mesh.hpp).
#include "pbf/render/solid_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pbf/geometry/triangle_mesh.hpp"

namespace pbf::render {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
// Tessellation: smooth enough at the README's image sizes, a few thousand triangles.
constexpr int kSegments = 48;  // around spheres and cylinders
constexpr int kRings = 24;     // sphere latitude bands

Vec3 normalised(const Vec3& v) {
    const float len = length(v);
    return len > 0.0f ? v * (1.0f / len) : Vec3{0.0f, 1.0f, 0.0f};
}

void vertex(SolidMesh& mesh, const Vec3& p, const Vec3& n) {
    mesh.data.insert(mesh.data.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
}

void triangle(SolidMesh& mesh, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = normalised(cross(b - a, c - a));
    vertex(mesh, a, n);
    vertex(mesh, b, n);
    vertex(mesh, c, n);
}

// Two unit vectors perpendicular to `axis` and to each other.
void basis(const Vec3& axis, Vec3& u, Vec3& v) {
    const Vec3 other = std::fabs(axis.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    u = normalised(cross(axis, other));
    v = cross(axis, u);
}

void appendBox(SolidMesh& mesh, const Aabb& box) {
    const Vec3 a = box.min, b = box.max;
    const Vec3 c[8] = {{a.x, a.y, a.z}, {b.x, a.y, a.z}, {b.x, b.y, a.z}, {a.x, b.y, a.z},
                       {a.x, a.y, b.z}, {b.x, a.y, b.z}, {b.x, b.y, b.z}, {a.x, b.y, b.z}};
    // Six faces, counter-clockwise seen from outside.
    const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                             {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
    for (const auto& f : faces) {
        triangle(mesh, c[f[0]], c[f[1]], c[f[2]]);
        triangle(mesh, c[f[0]], c[f[2]], c[f[3]]);
    }
}

void appendSphere(SolidMesh& mesh, const Vec3& center, float radius) {
    auto direction = [](int ring, int segment) {
        const float theta = kPi * float(ring) / float(kRings);  // from +y down
        const float phi = 2.0f * kPi * float(segment) / float(kSegments);
        return Vec3{std::sin(theta) * std::cos(phi), std::cos(theta),
                    -std::sin(theta) * std::sin(phi)};
    };
    for (int r = 0; r < kRings; ++r)
        for (int s = 0; s < kSegments; ++s) {
            const Vec3 n00 = direction(r, s), n01 = direction(r, s + 1);
            const Vec3 n10 = direction(r + 1, s), n11 = direction(r + 1, s + 1);
            auto add = [&](const Vec3& n) { vertex(mesh, center + n * radius, n); };
            if (r > 0) {  // no degenerate triangle at the poles
                add(n00);
                add(n10);
                add(n01);
            }
            if (r + 1 < kRings) {
                add(n01);
                add(n10);
                add(n11);
            }
        }
}

void appendCylinder(SolidMesh& mesh, const Vec3& base, const Vec3& axisIn, float radius,
                    float height) {
    const Vec3 axis = normalised(axisIn);
    Vec3 u, v;
    basis(axis, u, v);
    const Vec3 top = base + axis * height;
    auto rim = [&](int s) {
        const float phi = 2.0f * kPi * float(s) / float(kSegments);
        return u * std::cos(phi) + v * std::sin(phi);
    };
    for (int s = 0; s < kSegments; ++s) {
        const Vec3 r0 = rim(s), r1 = rim(s + 1);
        const Vec3 b0 = base + r0 * radius, b1 = base + r1 * radius;
        const Vec3 t0 = top + r0 * radius, t1 = top + r1 * radius;
        // Side with smooth normals.
        vertex(mesh, b0, r0);
        vertex(mesh, b1, r1);
        vertex(mesh, t1, r1);
        vertex(mesh, b0, r0);
        vertex(mesh, t1, r1);
        vertex(mesh, t0, r0);
        // Caps.
        vertex(mesh, top, axis);
        vertex(mesh, t0, axis);
        vertex(mesh, t1, axis);
        vertex(mesh, base, -axis);
        vertex(mesh, b1, -axis);
        vertex(mesh, b0, -axis);
    }
}

// The plane's cut through the domain box: the points where the plane crosses
// the box's 12 edges form a convex polygon (3 to 6 corners), drawn as a fan.
void appendPlane(SolidMesh& mesh, const Vec3& point, const Vec3& normalIn, const Aabb& domain) {
    const Vec3 n = normalised(normalIn);
    const Vec3 a = domain.min, b = domain.max;
    const Vec3 c[8] = {{a.x, a.y, a.z}, {b.x, a.y, a.z}, {b.x, b.y, a.z}, {a.x, b.y, a.z},
                       {a.x, a.y, b.z}, {b.x, a.y, b.z}, {b.x, b.y, b.z}, {a.x, b.y, b.z}};
    const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                              {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    std::vector<Vec3> corners;
    for (const auto& e : edges) {
        const float d0 = dot(c[e[0]] - point, n), d1 = dot(c[e[1]] - point, n);
        if ((d0 < 0.0f) == (d1 < 0.0f) || d0 == d1) continue;
        corners.push_back(c[e[0]] + (c[e[1]] - c[e[0]]) * (d0 / (d0 - d1)));
    }
    if (corners.size() < 3) return;
    Vec3 centre{};
    for (const Vec3& p : corners) centre += p;
    centre *= 1.0f / float(corners.size());
    Vec3 u, v;
    basis(n, u, v);
    std::sort(corners.begin(), corners.end(), [&](const Vec3& p, const Vec3& q) {
        return std::atan2(dot(p - centre, v), dot(p - centre, u)) <
               std::atan2(dot(q - centre, v), dot(q - centre, u));
    });
    for (std::size_t i = 0; i < corners.size(); ++i) {
        const Vec3& p = corners[i];
        const Vec3& q = corners[(i + 1) % corners.size()];
        vertex(mesh, centre, n);
        vertex(mesh, p, n);
        vertex(mesh, q, n);
    }
}

// OBJ meshes get smooth normals (area-weighted face normals summed per vertex).
void appendMesh(SolidMesh& mesh, const SolidDescription& solid) {
    const TriangleMesh tm = loadTriangleMesh(solid.file, solid.transform);
    std::vector<Vec3> normals(tm.vertices.size(), Vec3{});
    for (const auto& t : tm.triangles) {
        const Vec3 area =
            cross(tm.vertices[t[1]] - tm.vertices[t[0]], tm.vertices[t[2]] - tm.vertices[t[0]]);
        for (const std::uint32_t i : t) normals[i] += area;
    }
    for (const auto& t : tm.triangles)
        for (const std::uint32_t i : t) vertex(mesh, tm.vertices[i], normalised(normals[i]));
}

}  // namespace

void appendSolid(SolidMesh& mesh, const SolidDescription& solid, const Aabb& domain) {
    using Kind = SolidDescription::Kind;
    switch (solid.kind) {
        case Kind::Box:
            appendBox(mesh, solid.box);
            break;
        case Kind::Sphere:
            appendSphere(mesh, solid.center, solid.radius);
            break;
        case Kind::Cylinder:
            appendCylinder(mesh, solid.base, solid.axis, solid.radius, solid.height);
            break;
        case Kind::Plane:
            appendPlane(mesh, solid.point, solid.normal, domain);
            break;
        case Kind::Mesh:
            appendMesh(mesh, solid);
            break;
    }
}

std::vector<SolidMesh> tessellateBodyShapes(const Scene& scene) {
    using Kind = SolidDescription::Kind;
    std::vector<SolidMesh> shapes;
    for (const RigidBodyDescription& body : scene.rigidBodies) {
        SolidDescription local = body.shape;  // the shape in its own frame
        switch (local.kind) {
            case Kind::Box: {
                const Vec3 half = local.box.extent() * 0.5f;
                local.box = {-half, half};
                break;
            }
            case Kind::Sphere:
                local.center = {};
                break;
            case Kind::Cylinder:
                local.base = {0.0f, -0.5f * local.height, 0.0f};
                local.axis = {0.0f, 1.0f, 0.0f};
                break;
            case Kind::Mesh:
                local.transform.rotationDegrees = {};
                local.transform.translation = {};
                break;
            case Kind::Plane:
                break;
        }
        SolidMesh mesh;
        try {
            appendSolid(mesh, local, scene.simulation.domain);
        } catch (const SolidError& e) {
            throw SceneError(scene.source + ": " + body.field + ".file: " + e.what());
        }
        shapes.push_back(std::move(mesh));
    }
    return shapes;
}

void appendPosed(SolidMesh& out, const SolidMesh& shape, const Pose& pose) {
    out.data.reserve(out.data.size() + shape.data.size());
    for (std::size_t k = 0; k + 5 < shape.data.size(); k += 6) {
        const Vec3 p = pose.toWorld({shape.data[k], shape.data[k + 1], shape.data[k + 2]});
        const Vec3 n =
            pose.directionToWorld({shape.data[k + 3], shape.data[k + 4], shape.data[k + 5]});
        out.data.insert(out.data.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
    }
}

SolidMesh posedSolids(const SolidMesh& statics, const std::vector<SolidMesh>& bodyShapes,
                      const std::vector<DrivenShape>& driven, const World& world) {
    SolidMesh mesh = statics;
    for (std::size_t k = 0; k < bodyShapes.size() && k < world.bodyCount(); ++k)
        appendPosed(mesh, bodyShapes[k], world.solidMotion(world.bodyInfos()[k].solid).pose);
    appendDriven(mesh, driven, world.time());
    return mesh;
}

std::vector<DrivenShape> tessellateDrivenSolids(const Scene& scene) {
    std::vector<DrivenShape> shapes;
    for (const SolidDescription& solid : scene.solids) {
        if (!solid.motion.moves()) continue;
        DrivenShape shape;
        shape.motion = solid.motion;
        shape.pivot = pivotOf(solid);
        SolidDescription own = solid;
        if (solid.kind == SolidDescription::Kind::Mesh) {
            // The mesh in its file's frame (scaled); its transform is the rest pose.
            shape.rest = solid.transform.pose();
            own.transform.rotationDegrees = {};
            own.transform.translation = {};
        }
        try {
            appendSolid(shape.mesh, own, scene.simulation.domain);
        } catch (const SolidError& e) {
            throw SceneError(scene.source + ": " + solid.field + ".file: " + e.what());
        }
        shapes.push_back(std::move(shape));
    }
    return shapes;
}

void appendDriven(SolidMesh& out, const std::vector<DrivenShape>& driven, double time) {
    for (const DrivenShape& shape : driven)
        appendPosed(out, shape.mesh, motionAt(shape.motion, shape.rest, shape.pivot, time).pose);
}

SolidMesh tessellateSolids(const Scene& scene) {
    SolidMesh mesh;
    for (const SolidDescription& solid : scene.solids) {
        if (solid.motion.moves()) continue;  // tessellateDrivenSolids
        try {
            appendSolid(mesh, solid, scene.simulation.domain);
        } catch (const SolidError& e) {
            throw SceneError(scene.source + ": " + solid.field + ".file: " + e.what());
        }
    }
    return mesh;
}

}  // namespace pbf::render
