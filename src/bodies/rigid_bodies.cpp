#include "bodies/rigid_bodies.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "bodies/contact_world.hpp"
#include "bodies/mass_properties.hpp"
#include "geometry/boundary_scale.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/geometry/triangle_mesh.hpp"

namespace pbf::detail {
namespace {

using Kind = SolidDescription::Kind;

Vec3 normalised(const Vec3& v) {
    const float len = length(v);
    return len > 0.0f ? v * (1.0f / len) : Vec3{0.0f, 1.0f, 0.0f};
}

Quat normalised(const Quat& q) {
    const float n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    return {q.w / n, q.x / n, q.y / n, q.z / n};
}

// The shortest rotation taking the y axis to `axis` (a unit vector).
Quat rotationFromY(const Vec3& axis) {
    const Vec3 y{0.0f, 1.0f, 0.0f};
    const float c = dot(y, axis);
    if (c < -0.999999f) return {0.0f, 1.0f, 0.0f, 0.0f};  // half a turn about x
    const Vec3 v = cross(y, axis);
    return normalised(Quat{1.0f + c, v.x, v.y, v.z});
}

std::string scenePrefix(const BodiesSetup& def) {
    return def.source + ": ";
}

std::string fieldOf(const std::string& given, const char* list, std::size_t i) {
    return given.empty() ? fmt::format("{}[{}]", list, i) : given;
}

Transform scaleOnly(const Transform& t) {
    Transform s;
    s.scale = t.scale;
    return s;
}

MeshSolidOptions meshOptions(const SimulationParams& sim) {
    MeshSolidOptions options;  // as buildSolids makes them for static meshes
    options.voxelSize = 0.5f * sim.particleRadius;
    options.bandWidth = sim.kernelRadius() + 2.0f * sim.particleRadius;
    options.shellThickness = sim.particleRadius;
    return options;
}

// A static solid as Bullet sees it.
StaticCollider staticCollider(const BodiesSetup& def, const SolidDescription& d,
                              const std::string& field) {
    StaticCollider s;
    s.field = field;
    ContactShape& shape = s.shape;
    switch (d.kind) {
        case Kind::Box:
            shape.kind = ContactShape::Kind::Box;
            shape.halfExtents = d.box.extent() * 0.5f;
            s.pose.position = (d.box.min + d.box.max) * 0.5f;
            break;
        case Kind::Sphere:
            shape.kind = ContactShape::Kind::Sphere;
            shape.radius = d.radius;
            s.pose.position = d.center;
            break;
        case Kind::Plane:
            shape.kind = ContactShape::Kind::Plane;
            shape.normal = normalised(d.normal);
            shape.offset = dot(shape.normal, d.point);
            break;
        case Kind::Cylinder: {
            const Vec3 axis = normalised(d.axis);
            shape.kind = ContactShape::Kind::Cylinder;
            shape.halfExtents = {d.radius, 0.5f * d.height, d.radius};
            s.pose = {d.base + axis * (0.5f * d.height), rotationFromY(axis)};
            break;
        }
        case Kind::Mesh: {
            TriangleMesh mesh;
            try {
                mesh = loadTriangleMesh(d.file, scaleOnly(d.transform));
            } catch (const SolidError& e) {
                throw SceneError(scenePrefix(def) + field + ".file: " + e.what());
            }
            shape.kind = ContactShape::Kind::TriangleMesh;
            shape.points = std::move(mesh.vertices);
            shape.triangles = std::move(mesh.triangles);
            s.pose = d.transform.pose();
            break;
        }
    }
    return s;
}

// The six walls of the domain, each a half-space whose solid side is outside.
std::vector<StaticCollider> wallColliders(const Aabb& domain) {
    std::vector<StaticCollider> walls;
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a) {
        for (const float side : {1.0f, -1.0f}) {
            StaticCollider w;
            w.field = "the domain walls";
            w.shape.kind = ContactShape::Kind::Plane;
            w.shape.normal = axes[a] * side;  // pointing into the domain
            w.shape.offset = side > 0.0f ? domain.min[a] : -domain.max[a];
            walls.push_back(std::move(w));
        }
    }
    return walls;
}

struct BuiltBody {
    std::unique_ptr<Solid> surface;
    RigidBodyInfo info;
    RigidBodyState state;
    BodyCollider collider;
};

BuiltBody buildBody(const BodiesSetup& def, const RigidBodyDescription& b,
                    const std::string& field) {
    const SolidDescription& d = b.shape;
    BuiltBody out;
    RigidBodyInfo& info = out.info;
    info.field = field;
    out.collider.field = field;
    ContactShape& shape = out.collider.shape;
    MassProperties unit;  // per unit density, in the shape's frame
    Pose shapePose;       // the shape's frame in the world
    switch (d.kind) {
        case Kind::Box: {
            const Vec3 half = d.box.extent() * 0.5f;
            out.surface = makeBoxSolid({-half, half});
            unit = boxMassProperties(half);
            shape.kind = ContactShape::Kind::Box;
            shape.halfExtents = half;
            shapePose = {(d.box.min + d.box.max) * 0.5f,
                         fromEulerDegrees(d.transform.rotationDegrees)};
            info.boundingRadius = length(half);
            info.describe =
                fmt::format("box {:g} x {:g} x {:g} m", 2 * half.x, 2 * half.y, 2 * half.z);
            break;
        }
        case Kind::Sphere:
            out.surface = makeSphereSolid({}, d.radius);
            unit = sphereMassProperties(d.radius);
            shape.kind = ContactShape::Kind::Sphere;
            shape.radius = d.radius;
            shapePose.position = d.center;
            info.boundingRadius = d.radius;
            info.describe = fmt::format("sphere of radius {:g} m", d.radius);
            break;
        case Kind::Cylinder: {
            const Vec3 axis = normalised(d.axis);
            out.surface = makeCylinderSolid({0.0f, -0.5f * d.height, 0.0f}, {0.0f, 1.0f, 0.0f},
                                            d.radius, d.height);
            unit = cylinderMassProperties(d.radius, d.height);
            shape.kind = ContactShape::Kind::Cylinder;
            shape.halfExtents = {d.radius, 0.5f * d.height, d.radius};
            shapePose = {d.base + axis * (0.5f * d.height), rotationFromY(axis)};
            info.boundingRadius = std::sqrt(d.radius * d.radius + 0.25f * d.height * d.height);
            info.describe =
                fmt::format("cylinder of radius {:g} m, height {:g} m", d.radius, d.height);
            break;
        }
        case Kind::Mesh: {
            TriangleMesh mesh;
            MeshInfo meshInfo;
            try {
                mesh = loadTriangleMesh(d.file, scaleOnly(d.transform));
                out.surface = loadMeshSolid(d.file, scaleOnly(d.transform),
                                            meshOptions(def.simulation), &meshInfo);
            } catch (const SolidError& e) {
                throw SceneError(scenePrefix(def) + field + ".file: " + e.what());
            }
            if (!meshInfo.closed())
                throw SceneError(scenePrefix(def) + field + ".file: " + d.file +
                                 fmt::format(": a rigid body's mesh must be closed (it needs an "
                                             "inside and a volume), this one has {} boundary and "
                                             "{} non-manifold edges",
                                             meshInfo.boundaryEdges, meshInfo.nonManifoldEdges));
            unit = meshMassProperties(mesh.vertices, mesh.triangles);
            if (!(unit.volume > 1e-12))
                throw SceneError(scenePrefix(def) + field + ".file: " + d.file +
                                 ": the mesh encloses no volume");
            shape.kind = ContactShape::Kind::ConvexHull;
            shape.points = std::move(mesh.vertices);  // moved to the body frame below
            shapePose = d.transform.pose();
            info.describe = fmt::format("mesh {} scaled ({:g}, {:g}, {:g}) ({} triangles)", d.file,
                                        d.transform.scale.x, d.transform.scale.y,
                                        d.transform.scale.z, meshInfo.triangles);
            break;
        }
        case Kind::Plane:
            throw SceneError(scenePrefix(def) + field + ".type: a plane cannot be a rigid body");
    }
    // The body frame: the centre of mass and the principal axes, found in the
    // shape's frame (they are the shape's own axes for box, sphere, cylinder).
    Quat principal;
    Vec3 moments;
    principalAxes(unit.inertia, principal, moments);
    const Vec3 centre{float(unit.centre[0]), float(unit.centre[1]), float(unit.centre[2])};
    const Pose bodyInShape{centre, principal};
    info.shapeInBody = {rotate(principal.conjugate(), -centre), principal.conjugate()};
    if (shape.kind == ContactShape::Kind::ConvexHull) {
        float radius = 0.0f;
        for (Vec3& p : shape.points) {
            p = bodyInShape.toLocal(p);
            radius = std::max(radius, length(p));
        }
        info.boundingRadius = radius;
    }
    info.volume = unit.volume;
    info.mass = b.mass > 0.0f ? double(b.mass) : double(b.density) * unit.volume;
    const double density = info.mass / unit.volume;
    info.inertia = moments * float(density);
    out.collider.mass = info.mass;
    out.collider.inertia = info.inertia;
    out.collider.friction = b.friction;
    out.collider.restitution = b.restitution;

    RigidBodyState& s = out.state;
    s.position = shapePose.toWorld(centre);
    s.orientation = normalised(shapePose.orientation * principal);
    s.velocity = b.velocity;
    s.angularVelocity = b.angularVelocity;
    return out;
}

}  // namespace

RigidBodies::RigidBodies(const BodiesSetup& def, SolidSet& solids) {
    if (def.bodies.empty()) return;
    std::vector<StaticCollider> statics;
    for (std::size_t i = 0; i < def.solids.size(); ++i)
        statics.push_back(
            staticCollider(def, def.solids[i], fieldOf(def.solids[i].field, "solids", i)));
    for (StaticCollider& w : wallColliders(def.simulation.domain)) statics.push_back(std::move(w));

    std::vector<BodyCollider> colliders;
    // Bodies of the same shape share their boundary-density grid.
    std::map<std::string, std::shared_ptr<const BoundaryScale>> scales;
    const SolverConstants constants = SolverConstants::from(def.simulation);
    for (std::size_t i = 0; i < def.bodies.size(); ++i) {
        const RigidBodyDescription& b = def.bodies[i];
        BuiltBody built = buildBody(def, b, fieldOf(b.field, "rigid_bodies", i));
        std::shared_ptr<const BoundaryScale>& scale = scales[built.info.describe];
        if (!scale)
            scale = std::make_shared<BoundaryScale>(
                *built.surface, constants.h, constants.wall.range, def.simulation.particleRadius);
        built.info.solid = solids.size();
        solids.add(std::move(built.surface), {}, /*coupled=*/true);
        solids.setBoundaryScale(built.info.solid, scale);
        infos_.push_back(std::move(built.info));
        states_.push_back(built.state);
        colliders.push_back(std::move(built.collider));
    }
    loads_.assign(infos_.size(), RigidBodyLoad{});
    // Contact shapes reach one particle radius beyond the surfaces: touching
    // surfaces keep one layer of particles between them (contact_world.hpp).
    contacts_ = std::make_unique<ContactWorld>(std::move(statics), std::move(colliders),
                                               def.simulation.particleRadius);
    contacts_->reset(states_);
    // Half a particle radius of overlap is tolerated; a body put on the
    // floor (or on another body) is lifted to the contact gap of 2 r in the
    // first steps.
    if (const auto overlap = contacts_->firstOverlap(0.5f * def.simulation.particleRadius))
        throw SceneError(scenePrefix(def) + *overlap +
                         " at the start: bodies must start apart from each other, the solids "
                         "and the domain walls");
    for (std::size_t i = 0; i < size(); ++i)
        solids.setMotion(infos_[i].solid, surfaceMotion(i, states_[i]));
}

RigidBodies::~RigidBodies() = default;

SolidMotion RigidBodies::surfaceMotion(std::size_t i, const RigidBodyState& s) const {
    const Pose body{s.position, s.orientation};
    const Pose& local = infos_[i].shapeInBody;
    const Pose shape{body.toWorld(local.position), s.orientation * local.orientation};
    // The solid's velocity is that of its frame's origin (SolidMotion::velocityAt).
    return {shape, s.velocity + cross(s.angularVelocity, shape.position - s.position),
            s.angularVelocity};
}

void RigidBodies::setState(std::size_t i, const RigidBodyState& state, SolidSet& solids) {
    states_.at(i) = state;
    states_[i].orientation = normalised(state.orientation);
    solids.setMotion(infos_[i].solid, surfaceMotion(i, states_[i]));
}

// Exactly the given bits (a checkpoint): normalising the orientation again
// would change its last bit and the resumed run would drift from the
// uninterrupted one.
void RigidBodies::setStates(std::vector<RigidBodyState> states, SolidSet& solids) {
    if (states.size() != size())
        throw std::invalid_argument(
            fmt::format("{} body states for {} rigid bodies", states.size(), size()));
    states_ = std::move(states);
    for (std::size_t i = 0; i < size(); ++i)
        solids.setMotion(infos_[i].solid, surfaceMotion(i, states_[i]));
}

float RigidBodies::maxSurfaceSpeed() const {
    float fastest = 0.0f;
    for (std::size_t i = 0; i < size(); ++i)
        fastest =
            std::max(fastest, length(states_[i].velocity) +
                                  length(states_[i].angularVelocity) * infos_[i].boundingRadius);
    return fastest;
}

std::size_t RigidBodies::firstBadBody() const {
    const auto finite = [](const Vec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    for (std::size_t i = 0; i < size(); ++i) {
        const RigidBodyState& s = states_[i];
        const Quat& q = s.orientation;
        if (!finite(s.position) || !finite(s.velocity) || !finite(s.angularVelocity) ||
            !std::isfinite(q.w) || !std::isfinite(q.x) || !std::isfinite(q.y) ||
            !std::isfinite(q.z))
            return i;
    }
    return size();
}

void RigidBodies::beginFrame(double frameDuration) {
    if (empty()) return;
    frameDuration_ = frameDuration;
    loads_.assign(size(), RigidBodyLoad{});
    contacts_->reset(states_);
}

void RigidBodies::placeForFluid(double dt, SolidSet& solids) const {
    const float h = static_cast<float>(dt);
    for (std::size_t i = 0; i < size(); ++i) {
        RigidBodyState ahead = states_[i];
        ahead.position += ahead.velocity * h;
        // q += dt/2 (0, omega) q: the orientation after dt at constant omega
        // (to first order, normalised).
        const Vec3& w = ahead.angularVelocity;
        const Quat spin = Quat{0.0f, w.x, w.y, w.z} * ahead.orientation;
        const Quat& q = ahead.orientation;
        ahead.orientation = normalised(Quat{q.w + 0.5f * h * spin.w, q.x + 0.5f * h * spin.x,
                                            q.y + 0.5f * h * spin.y, q.z + 0.5f * h * spin.z});
        solids.setMotion(infos_[i].solid, surfaceMotion(i, ahead));
    }
}

void RigidBodies::advance(double dt, const Vec3& gravity, std::span<const SolidReaction> reactions,
                          SolidSet& solids) {
    if (empty()) return;
    forces_.assign(size(), Vec3{});
    torques_.assign(size(), Vec3{});
    for (std::size_t i = 0; i < size(); ++i) {
        const std::size_t k = infos_[i].solid;
        if (k >= reactions.size()) continue;  // no fluid touched anything
        const SolidReaction& r = reactions[k];
        // The backend's torque is about the surface frame's origin where the
        // fluid saw it; about the centre of mass: tau + (o - c) x F.
        const Pose& surface = solids.motion(k).pose;
        const Vec3 centre = surface.toWorld(
            rotate(infos_[i].shapeInBody.orientation.conjugate(), -infos_[i].shapeInBody.position));
        forces_[i] = r.force;
        torques_[i] = r.torque + cross(surface.position - centre, r.force);
        const float share = static_cast<float>(dt / frameDuration_);
        loads_[i].force += forces_[i] * share;
        loads_[i].torque += torques_[i] * share;
    }
    contacts_->step(dt, gravity, forces_, torques_);
    contacts_->read(states_);
    for (std::size_t i = 0; i < size(); ++i)
        solids.setMotion(infos_[i].solid, surfaceMotion(i, states_[i]));
}

}  // namespace pbf::detail
