#include "bodies/contact_world.hpp"

#include <LinearMath/btConvexHullComputer.h>
#include <btBulletDynamicsCommon.h>
#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace pbf::detail {
namespace {

btVector3 toBullet(const Vec3& v) {
    return {v.x, v.y, v.z};
}

btTransform toBullet(const Pose& p) {
    const Quat& q = p.orientation;
    return btTransform(btQuaternion(q.x, q.y, q.z, q.w), toBullet(p.position));
}

Vec3 fromBullet(const btVector3& v) {
    return {float(v.x()), float(v.y()), float(v.z())};
}

struct BuiltShape {
    std::unique_ptr<btCollisionShape> shape;
    std::unique_ptr<btTriangleMesh> mesh;  // owned triangles of a TriangleMesh shape
};

// Every shape dilated by `d` (the Minkowski sum with a sphere of radius d:
// Bullet's convex shapes are a core shape plus a margin sphere, so the core
// keeps the true size and the margin is d).
BuiltShape build(const ContactShape& s, float d) {
    using Kind = ContactShape::Kind;
    const Vec3 grow{d, d, d};
    BuiltShape b;
    switch (s.kind) {
        case Kind::Box:
            // btBoxShape keeps its outer size when the margin changes.
            b.shape = std::make_unique<btBoxShape>(toBullet(s.halfExtents + grow));
            b.shape->setMargin(d);
            break;
        case Kind::Sphere:
            b.shape = std::make_unique<btSphereShape>(s.radius + d);  // its margin is its radius
            break;
        case Kind::Cylinder:
            b.shape = std::make_unique<btCylinderShape>(toBullet(s.halfExtents + grow));
            b.shape->setMargin(d);
            break;
        case Kind::ConvexHull: {
            // The hull's corners only: a mesh body's contact shape is its
            // convex hull (Bullet has no exact concave-concave contacts for
            // moving meshes; the fluid sees the exact mesh).
            std::vector<double> coordinates;
            for (const Vec3& p : s.points) coordinates.insert(coordinates.end(), {p.x, p.y, p.z});
            btConvexHullComputer hull;
            hull.compute(coordinates.data(), int(3 * sizeof(double)), int(s.points.size()), 0.0,
                         0.0);
            auto shape = std::make_unique<btConvexHullShape>();
            for (int k = 0; k < hull.vertices.size(); ++k) shape->addPoint(hull.vertices[k], false);
            shape->recalcLocalAabb();
            shape->setMargin(d);  // added outside the hull
            b.shape = std::move(shape);
            break;
        }
        case Kind::Plane:
            b.shape = std::make_unique<btStaticPlaneShape>(toBullet(s.normal), s.offset + d);
            break;
        case Kind::TriangleMesh: {
            b.mesh = std::make_unique<btTriangleMesh>();
            for (const auto& t : s.triangles)
                b.mesh->addTriangle(toBullet(s.points[t[0]]), toBullet(s.points[t[1]]),
                                    toBullet(s.points[t[2]]), false);
            b.shape = std::make_unique<btBvhTriangleMeshShape>(b.mesh.get(), true);
            b.shape->setMargin(d);  // each triangle's margin: a dilated surface
            break;
        }
    }
    return b;
}

}  // namespace

struct ContactWorld::Impl {
    std::vector<StaticCollider> statics;
    std::vector<BodyCollider> bodies;
    std::vector<BuiltShape> staticShapes;
    std::vector<BuiltShape> bodyShapes;
    double dilation = 0.0;
    btDefaultCollisionConfiguration configuration;
    // Rebuilt by reset():
    std::unique_ptr<btCollisionDispatcher> dispatcher;
    std::unique_ptr<btDbvtBroadphase> broadphase;
    std::unique_ptr<btSequentialImpulseConstraintSolver> solver;
    std::unique_ptr<btDiscreteDynamicsWorld> world;
    std::vector<std::unique_ptr<btRigidBody>> staticObjects;
    std::vector<std::unique_ptr<btRigidBody>> bodyObjects;

    void clear() {
        if (world) {
            for (auto& o : bodyObjects) world->removeRigidBody(o.get());
            for (auto& o : staticObjects) world->removeRigidBody(o.get());
        }
        world.reset();
        solver.reset();
        broadphase.reset();
        dispatcher.reset();
        bodyObjects.clear();
        staticObjects.clear();
    }
    ~Impl() { clear(); }

    std::string nameOf(const btCollisionObject* o) const {
        const int k = o->getUserIndex();
        return k >= 0 ? bodies[std::size_t(k)].field : statics[std::size_t(-1 - k)].field;
    }
};

ContactWorld::ContactWorld(std::vector<StaticCollider> statics, std::vector<BodyCollider> bodies,
                           float dilation)
    : impl_(std::make_unique<Impl>()) {
    impl_->dilation = dilation;
    impl_->statics = std::move(statics);
    impl_->bodies = std::move(bodies);
    for (const StaticCollider& s : impl_->statics)
        impl_->staticShapes.push_back(build(s.shape, dilation));
    for (const BodyCollider& b : impl_->bodies)
        impl_->bodyShapes.push_back(build(b.shape, dilation));
}

ContactWorld::~ContactWorld() = default;

void ContactWorld::reset(std::span<const RigidBodyState> states) {
    Impl& m = *impl_;
    if (states.size() != m.bodies.size())
        throw std::invalid_argument("ContactWorld::reset: wrong number of body states");
    m.clear();
    m.dispatcher = std::make_unique<btCollisionDispatcher>(&m.configuration);
    m.broadphase = std::make_unique<btDbvtBroadphase>();
    m.solver = std::make_unique<btSequentialImpulseConstraintSolver>();
    m.world = std::make_unique<btDiscreteDynamicsWorld>(m.dispatcher.get(), m.broadphase.get(),
                                                        m.solver.get(), &m.configuration);
    m.world->getSolverInfo().m_numIterations = 20;
    for (std::size_t k = 0; k < m.statics.size(); ++k) {
        btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, m.staticShapes[k].shape.get());
        // Bullet multiplies the two sides' coefficients: 1 on the static
        // side gives the body's own friction and restitution.
        info.m_friction = 1.0;
        info.m_restitution = 1.0;
        auto object = std::make_unique<btRigidBody>(info);
        object->setWorldTransform(toBullet(m.statics[k].pose));
        object->setUserIndex(-1 - int(k));
        m.world->addRigidBody(object.get());
        m.staticObjects.push_back(std::move(object));
    }
    for (std::size_t k = 0; k < m.bodies.size(); ++k) {
        const BodyCollider& b = m.bodies[k];
        const RigidBodyState& s = states[k];
        btRigidBody::btRigidBodyConstructionInfo info(b.mass, nullptr, m.bodyShapes[k].shape.get(),
                                                      toBullet(b.inertia));
        info.m_friction = b.friction;
        info.m_restitution = b.restitution;
        info.m_linearDamping = 0.0;  // drag is the fluid's business
        info.m_angularDamping = 0.0;
        auto object = std::make_unique<btRigidBody>(info);
        object->setWorldTransform(toBullet(Pose{s.position, s.orientation}));
        object->setLinearVelocity(toBullet(s.velocity));
        object->setAngularVelocity(toBullet(s.angularVelocity));
        object->setActivationState(DISABLE_DEACTIVATION);  // the fluid keeps pushing
        object->setUserIndex(int(k));
        m.world->addRigidBody(object.get());
        m.bodyObjects.push_back(std::move(object));
    }
}

void ContactWorld::step(double dt, const Vec3& gravity, std::span<const Vec3> forces,
                        std::span<const Vec3> torques) {
    Impl& m = *impl_;
    if (!m.world) throw std::logic_error("ContactWorld::step before reset");
    m.world->setGravity(toBullet(gravity));
    for (std::size_t k = 0; k < m.bodyObjects.size(); ++k) {
        m.bodyObjects[k]->applyCentralForce(toBullet(forces[k]));
        m.bodyObjects[k]->applyTorque(toBullet(torques[k]));
    }
    // maxSubSteps = 0: exactly one step of dt (the fluid's substep).
    m.world->stepSimulation(dt, 0, dt);
}

void ContactWorld::read(std::span<RigidBodyState> states) const {
    const Impl& m = *impl_;
    for (std::size_t k = 0; k < m.bodyObjects.size(); ++k) {
        const btRigidBody& o = *m.bodyObjects[k];
        const btTransform& t = o.getCenterOfMassTransform();
        const btQuaternion q = t.getRotation();
        states[k].position = fromBullet(t.getOrigin());
        states[k].orientation = {float(q.w()), float(q.x()), float(q.y()), float(q.z())};
        states[k].velocity = fromBullet(o.getLinearVelocity());
        states[k].angularVelocity = fromBullet(o.getAngularVelocity());
    }
}

std::optional<std::string> ContactWorld::firstOverlap(float tolerance) const {
    Impl& m = *impl_;
    if (!m.world) return std::nullopt;
    m.world->performDiscreteCollisionDetection();
    btDispatcher& dispatcher = *m.world->getDispatcher();
    std::optional<std::string> found;
    double deepest = -tolerance - 2.0 * m.dilation;  // between the true surfaces
    for (int i = 0; i < dispatcher.getNumManifolds(); ++i) {
        const btPersistentManifold& manifold = *dispatcher.getManifoldByIndexInternal(i);
        for (int c = 0; c < manifold.getNumContacts(); ++c) {
            const double distance = manifold.getContactPoint(c).getDistance();
            if (distance >= deepest) continue;
            deepest = distance;
            const btCollisionObject* a = manifold.getBody0();
            const btCollisionObject* b = manifold.getBody1();
            if (a->getUserIndex() < 0) std::swap(a, b);  // name the body first
            found = fmt::format("{} overlaps {} by {:.3g} m", m.nameOf(a), m.nameOf(b),
                                -distance - 2.0 * m.dilation);
        }
    }
    return found;
}

}  // namespace pbf::detail
