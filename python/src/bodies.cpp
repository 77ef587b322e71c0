// Rigid bodies from Python: their definition (pbf.RigidBodyDescription, in
// WorldDef.rigid_bodies) and their state in a running world (world.bodies).
//
//   d.rigid_bodies.append(pbf.RigidBodyDescription(
//       pbf.SolidDescription.box((0.4, 0.3, 0.1), (0.5, 0.4, 0.2)), density=500))
//   world = pbf.World(d)
//   world.step_frame()
//   b = world.bodies[0]     # a snapshot: b.position, b.orientation, b.velocity, ...
#include "bindings.hpp"
#include "world_handle.hpp"

namespace pbf::python {
namespace {

// One body of a world at the moment it was read.
struct BodySnapshot {
    std::size_t index = 0;
    RigidBodyInfo info;
    RigidBodyState state;
    RigidBodyLoad load;
};

py::tuple quaternion(const Quat& q) {
    return py::make_tuple(q.w, q.x, q.y, q.z);
}

Quat quaternionFrom(const py::handle& value) {
    const auto v = value.cast<std::vector<float>>();
    if (v.size() != 4) throw py::value_error("orientation: expected (w, x, y, z)");
    return {v[0], v[1], v[2], v[3]};
}

void bindDescription(py::module_& m) {
    const RigidBodyDescription defaults;
    py::class_<RigidBodyDescription>(
        m, "RigidBodyDescription",
        "A rigid body (docs/scenes.md, \"rigid_bodies\"): a shape (a SolidDescription: box, "
        "sphere, cylinder or closed mesh) with exactly one of density (kg/m^3) and mass (kg), "
        "initial velocity and angular velocity, and contact friction and restitution.")
        .def(py::init([](const SolidDescription& shape, float density, float mass,
                         const Vec3& velocity, const Vec3& angularVelocity, float friction,
                         float restitution) {
                 RigidBodyDescription b;
                 b.shape = shape;
                 b.density = density;
                 b.mass = mass;
                 b.velocity = velocity;
                 b.angularVelocity = angularVelocity;
                 b.friction = friction;
                 b.restitution = restitution;
                 return b;
             }),
             py::arg("shape"), py::arg("density") = 0.0f, py::arg("mass") = 0.0f,
             py::arg("velocity") = Vec3{}, py::arg("angular_velocity") = Vec3{},
             py::arg("friction") = defaults.friction, py::arg("restitution") = defaults.restitution)
        .def_readwrite("shape", &RigidBodyDescription::shape)
        .def_property("density", floatGetter(&RigidBodyDescription::density),
                      floatSetter(&RigidBodyDescription::density), "kg/m^3 (0: use mass)")
        .def_property("mass", floatGetter(&RigidBodyDescription::mass),
                      floatSetter(&RigidBodyDescription::mass), "kg (0: use density)")
        .def_readwrite("velocity", &RigidBodyDescription::velocity, "m/s")
        .def_readwrite("angular_velocity", &RigidBodyDescription::angularVelocity, "rad/s")
        .def_property("friction", floatGetter(&RigidBodyDescription::friction),
                      floatSetter(&RigidBodyDescription::friction), "[0, 10]")
        .def_property("restitution", floatGetter(&RigidBodyDescription::restitution),
                      floatSetter(&RigidBodyDescription::restitution), "[0, 1]")
        .def_property(
            "adhesion",
            [](const RigidBodyDescription& b) { return shortestDouble(b.shape.adhesion); },
            [](RigidBodyDescription& b, float a) { b.shape.adhesion = a; },
            "wetting with surface tension (shape.adhesion), [0, 1]")
        .def_readwrite("field", &RigidBodyDescription::field,
                       "name in messages, e.g. \"rigid_bodies[0]\"")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "RigidBodyDescription",
                          {"shape", "density", "mass", "velocity", "angular_velocity"});
        });
}

void bindSnapshot(py::module_& m) {
    py::class_<BodySnapshot>(m, "RigidBody",
                             "A rigid body of a world as it was when read (world.bodies): "
                             "what it is and its state, SI units, world axes.")
        .def_readonly("index", &BodySnapshot::index)
        .def_property_readonly("field", [](const BodySnapshot& b) { return b.info.field; })
        .def_property_readonly("shape", [](const BodySnapshot& b) { return b.info.describe; })
        .def_property_readonly(
            "mass", [](const BodySnapshot& b) { return b.info.mass; }, "kg")
        .def_property_readonly(
            "volume", [](const BodySnapshot& b) { return b.info.volume; }, "m^3")
        .def_property_readonly(
            "inertia", [](const BodySnapshot& b) { return b.info.inertia; },
            "principal moments, kg m^2")
        .def_property_readonly(
            "solid", [](const BodySnapshot& b) { return b.info.solid; },
            "index of its surface in world.solids")
        .def_property_readonly(
            "position", [](const BodySnapshot& b) { return b.state.position; }, "centre of mass, m")
        .def_property_readonly(
            "orientation", [](const BodySnapshot& b) { return quaternion(b.state.orientation); },
            "unit quaternion (w, x, y, z) of the principal axes")
        .def_property_readonly(
            "velocity", [](const BodySnapshot& b) { return b.state.velocity; }, "m/s")
        .def_property_readonly(
            "angular_velocity", [](const BodySnapshot& b) { return b.state.angularVelocity; },
            "rad/s")
        .def_property_readonly(
            "fluid_force", [](const BodySnapshot& b) { return b.load.force; },
            "N, the fluid's push averaged over the last frame")
        .def_property_readonly(
            "fluid_torque", [](const BodySnapshot& b) { return b.load.torque; },
            "N m about the centre of mass, averaged over the last frame")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "RigidBody",
                          {"index", "shape", "mass", "position", "orientation", "velocity",
                           "angular_velocity"});
        });
}

}  // namespace

void bindBodyDescription(py::module_& m) {
    bindDescription(m);
}

void bindBodies(py::module_& m, py::class_<WorldHandle, std::shared_ptr<WorldHandle>>& world) {
    bindSnapshot(m);
    world
        .def_property_readonly(
            "bodies",
            [](WorldHandle& h) {
                return h.locked([](World& w) {
                    std::vector<BodySnapshot> bodies;
                    for (std::size_t k = 0; k < w.bodyCount(); ++k)
                        bodies.push_back(
                            {k, w.bodyInfos()[k], w.bodyStates()[k], w.bodyLoads()[k]});
                    return bodies;
                });
            },
            "The rigid bodies (pbf.RigidBody snapshots, in definition order).")
        .def(
            "set_body_state",
            [](WorldHandle& h, std::size_t index, const py::handle& position,
               const py::handle& orientation, const py::handle& velocity,
               const py::handle& angularVelocity) {
                h.locked([&](World& w) {
                    if (index >= w.bodyCount())
                        throw py::index_error("no rigid body " + std::to_string(index));
                    RigidBodyState s = w.bodyStates()[index];
                    if (!position.is_none()) s.position = position.cast<Vec3>();
                    if (!orientation.is_none()) s.orientation = quaternionFrom(orientation);
                    if (!velocity.is_none()) s.velocity = velocity.cast<Vec3>();
                    if (!angularVelocity.is_none())
                        s.angularVelocity = angularVelocity.cast<Vec3>();
                    w.setBodyState(index, s);
                });
            },
            py::arg("index"), py::arg("position") = py::none(), py::arg("orientation") = py::none(),
            py::arg("velocity") = py::none(), py::arg("angular_velocity") = py::none(),
            "Changes body `index` between frames: centre of mass (m), orientation (w, x, y, z), "
            "velocity (m/s), angular velocity (rad/s); what is not given is kept.");
}

}  // namespace pbf::python
