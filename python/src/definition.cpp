// The world definition (include/pbf/world/world_def.hpp) and scene files
// (include/pbf/io/scene.hpp): plain data that a pbf.World is built from.
//
//   d = pbf.WorldDef(name="column")
//   d.simulation.domain = ((0, 0, 0), (1.6, 0.6, 0.2))
//   d.fluid_blocks.append(pbf.FluidBlock((0, 0, 0), (0.2, 0.4, 0.2)))
//   d.solids.append(pbf.SolidDescription.sphere((0.8, 0.1, 0.1), 0.05))
//   world = pbf.World(d)
#include "bindings.hpp"
#include "scene_file.hpp"

namespace pbf::python {
namespace {

using Kind = SolidDescription::Kind;

const char* kindName(Kind kind) {
    switch (kind) {
        case Kind::Box:
            return "box";
        case Kind::Sphere:
            return "sphere";
        case Kind::Plane:
            return "plane";
        case Kind::Cylinder:
            return "cylinder";
        case Kind::Mesh:
            return "mesh";
    }
    return "?";
}

Kind parseKind(const std::string& name) {
    for (Kind k : {Kind::Box, Kind::Sphere, Kind::Plane, Kind::Cylinder, Kind::Mesh})
        if (name == kindName(k)) return k;
    throw SceneError("type: expected box, sphere, plane, cylinder or mesh, got \"" + name + "\"");
}

// A mesh's scale: one number (uniform, as in scene files) or three.
Vec3 scaleFrom(const py::handle& scale) {
    if (py::isinstance<py::float_>(scale) || py::isinstance<py::int_>(scale)) {
        const float s = scale.cast<float>();
        return {s, s, s};
    }
    return scale.cast<Vec3>();
}

SolidDescription solid(Kind kind) {
    SolidDescription s;
    s.kind = kind;
    return s;
}

PrescribedMotion waveMaker(PrescribedMotion::Kind kind, float waveHeight, float period,
                           float depth, const Vec3& direction, float ramp) {
    PrescribedMotion motion;
    motion.kind = kind;
    motion.waveHeight = waveHeight;
    motion.period = period;
    motion.depth = depth;
    motion.direction = direction;
    motion.ramp = ramp;
    return motion;
}

// A solid's prescribed motion (pbf/geometry/prescribed_motion.hpp):
// Motion.oscillate / rotate / keyframes, the scene file's "motion".
void bindMotion(py::module_& m) {
    using MKind = PrescribedMotion::Kind;
    const auto withPivot = [](PrescribedMotion& motion, const py::object& pivot) {
        if (pivot.is_none()) return;
        motion.hasPivot = true;
        motion.pivot = pivot.cast<Vec3>();
    };
    py::class_<PrescribedMotion>(
        m, "Motion",
        "A solid's prescribed motion (docs/scenes.md, \"Moving solids\"): a displacement from "
        "where the solid's definition puts it, turning about `pivot` (default: the solid's "
        "centre). Make one with oscillate(), rotate() or keyframes(); set it as "
        "SolidDescription.motion.")
        .def(py::init<>())
        .def_static(
            "oscillate",
            [withPivot](const Vec3& amplitude, float angleAmplitude, const Vec3& axis, float period,
                        float phase, const py::object& pivot) {
                PrescribedMotion motion;
                motion.kind = MKind::Oscillate;
                motion.amplitude = amplitude;
                motion.angleAmplitude = angleAmplitude;
                motion.axis = axis;
                motion.period = period;
                motion.phaseDegrees = phase;
                withPivot(motion, pivot);
                return motion;
            },
            py::arg("amplitude") = Vec3{}, py::arg("angle_amplitude") = 0.0f,
            py::arg("axis") = Vec3{0, 1, 0}, py::arg("period") = 1.0f, py::arg("phase") = 0.0f,
            py::arg("pivot") = py::none(),
            "d = amplitude sin(2 pi t / period + phase) (m) and a turn of angle_amplitude "
            "sin(...) degrees about axis; phase in degrees.")
        .def_static(
            "rotate",
            [withPivot](const Vec3& axis, float speed, const py::object& pivot) {
                PrescribedMotion motion;
                motion.kind = MKind::Rotate;
                motion.axis = axis;
                motion.speedDegrees = speed;
                withPivot(motion, pivot);
                return motion;
            },
            py::arg("axis") = Vec3{0, 1, 0}, py::arg("speed") = 0.0f, py::arg("pivot") = py::none(),
            "A constant angular speed (degrees per second) about axis.")
        .def_static(
            "keyframes",
            [withPivot](const std::vector<py::tuple>& keys, const py::object& pivot) {
                PrescribedMotion motion;
                motion.kind = MKind::Keyframes;
                for (const py::tuple& key : keys) {
                    if (key.size() < 2 || key.size() > 3)
                        throw SceneError(
                            "motion.keys: each keyframe is (time, position) or (time, position, "
                            "rotation in degrees)");
                    MotionKey k;
                    k.time = key[0].cast<double>();
                    k.position = key[1].cast<Vec3>();
                    if (key.size() == 3) k.rotationDegrees = key[2].cast<Vec3>();
                    motion.keys.push_back(k);
                }
                withPivot(motion, pivot);
                return motion;
            },
            py::arg("keys"), py::arg("pivot") = py::none(),
            "Linear between (time, position[, rotation]) keyframes, held before the first and "
            "after the last; rotations in degrees (as a mesh's rotation).")
        .def_static(
            "piston",
            [](float waveHeight, float period, float depth, const Vec3& direction, float ramp) {
                return waveMaker(MKind::Piston, waveHeight, period, depth, direction, ramp);
            },
            py::arg("wave_height"), py::arg("period"), py::arg("depth"),
            py::arg("direction") = Vec3{1, 0, 0}, py::arg("ramp") = -1.0f,
            "A piston wave maker: the stroke that makes waves of wave_height (m) and period (s) "
            "in still water depth (m) deep, by first-order theory (Biesel); the amplitude rises "
            "over ramp s (default two periods).")
        .def_static(
            "flap",
            [](float waveHeight, float period, float depth, const Vec3& pivot,
               const Vec3& direction, float ramp) {
                PrescribedMotion motion =
                    waveMaker(MKind::Flap, waveHeight, period, depth, direction, ramp);
                motion.hasPivot = true;
                motion.pivot = pivot;
                return motion;
            },
            py::arg("wave_height"), py::arg("period"), py::arg("depth"), py::arg("pivot"),
            py::arg("direction") = Vec3{1, 0, 0}, py::arg("ramp") = -1.0f,
            "A flap wave maker hinged at pivot (on the floor).")
        .def(
            "describe", [](const PrescribedMotion& motion) { return describe(motion); },
            "A wave maker's wavelength and stroke; empty for other motions.")
        .def_property_readonly("kind",
                               [](const PrescribedMotion& motion) {
                                   switch (motion.kind) {
                                       case MKind::None:
                                           return "none";
                                       case MKind::Oscillate:
                                           return "oscillate";
                                       case MKind::Rotate:
                                           return "rotate";
                                       case MKind::Keyframes:
                                           return "keyframes";
                                       case MKind::Piston:
                                           return "piston";
                                       case MKind::Flap:
                                           return "flap";
                                   }
                                   return "?";
                               })
        .def(
            "pose_at",
            [](const PrescribedMotion& motion, double time, const Vec3& pivot) {
                const SolidMotion s = motionAt(motion, Pose{}, pivot, time);
                return py::make_tuple(s.pose.toWorld(Vec3{}), s.velocity, s.angularVelocity);
            },
            py::arg("time"), py::arg("pivot") = Vec3{},
            "Where the motion takes the point at the origin at `time` s (about `pivot`), its "
            "velocity (m/s) and the angular velocity (rad/s).");
}

void bindBlocksAndGuard(py::module_& m) {
    py::class_<FluidBlock>(m, "FluidBlock",
                           "A box of water filled with particles on a lattice of spacing 2 r.")
        .def(py::init([](const Vec3& min, const Vec3& max, const Vec3& velocity) {
                 return FluidBlock{{min, max}, velocity};
             }),
             py::arg("min"), py::arg("max"), py::arg("velocity") = Vec3{})
        .def(py::init([](const Aabb& box, const Vec3& velocity) {
                 return FluidBlock{box, velocity};
             }),
             py::arg("box"), py::arg("velocity") = Vec3{})
        .def_readwrite("box", &FluidBlock::box, "metres")
        .def_readwrite("velocity", &FluidBlock::velocity, "initial velocity, m/s")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "FluidBlock", {"box", "velocity"});
        });

    py::class_<GuardParams>(m, "GuardParams",
                            "The state guard: a frame fails when a particle is faster than "
                            "max_speed (m/s) or, when max_speed is 0, than max_speed_factor times "
                            "the free-fall speed over the domain diagonal.")
        .def(py::init([](float maxSpeed, float maxSpeedFactor) {
                 return GuardParams{maxSpeed, maxSpeedFactor};
             }),
             py::arg("max_speed") = GuardParams{}.maxSpeed,
             py::arg("max_speed_factor") = GuardParams{}.maxSpeedFactor)
        .def_property("max_speed", floatGetter(&GuardParams::maxSpeed),
                      floatSetter(&GuardParams::maxSpeed), "m/s, [0, 1e6]; 0: automatic")
        .def_property("max_speed_factor", floatGetter(&GuardParams::maxSpeedFactor),
                      floatSetter(&GuardParams::maxSpeedFactor), "[1, 1e4]")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "GuardParams", {"max_speed", "max_speed_factor"});
        });
}

void bindSolids(py::module_& m) {
    py::class_<Transform>(m, "Transform",
                          "Placement of a mesh: p' = rotation(p * scale) + translation, rotation "
                          "in degrees about x, then y, then z.")
        .def(py::init([](const py::handle& scale, const Vec3& rotation, const Vec3& translation) {
                 return Transform{scaleFrom(scale), rotation, translation};
             }),
             py::arg("scale") = 1.0f, py::arg("rotation") = Vec3{}, py::arg("translation") = Vec3{})
        .def_readwrite("scale", &Transform::scale)
        .def_readwrite("rotation", &Transform::rotationDegrees, "degrees")
        .def_readwrite("translation", &Transform::translation, "metres")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "Transform", {"scale", "rotation", "translation"});
        });

    py::class_<SolidDescription>(m, "SolidDescription",
                                 "A static solid (docs/scenes.md, \"solids\"); make one with "
                                 "box(), sphere(), plane(), cylinder() or mesh().")
        .def(py::init<>())
        .def_static(
            "box",
            [](const Aabb& box) {
                SolidDescription s = solid(Kind::Box);
                s.box = box;
                return s;
            },
            py::arg("box"), "A box solid, e.g. box(((0.6, 0, 0), (0.7, 0.2, 0.4))).")
        .def_static(
            "box",
            [](const Vec3& min, const Vec3& max) {
                SolidDescription s = solid(Kind::Box);
                s.box = {min, max};
                return s;
            },
            py::arg("min"), py::arg("max"))
        .def_static(
            "sphere",
            [](const Vec3& center, float radius) {
                SolidDescription s = solid(Kind::Sphere);
                s.center = center;
                s.radius = radius;
                return s;
            },
            py::arg("center"), py::arg("radius"))
        .def_static(
            "plane",
            [](const Vec3& point, const Vec3& normal) {
                SolidDescription s = solid(Kind::Plane);
                s.point = point;
                s.normal = normal;
                return s;
            },
            py::arg("point"), py::arg("normal"),
            "Half-space below the plane: solid where dot(p - point, normal) < 0.")
        .def_static(
            "cylinder",
            [](const Vec3& base, const Vec3& axis, float radius, float height) {
                SolidDescription s = solid(Kind::Cylinder);
                s.base = base;
                s.axis = axis;
                s.radius = radius;
                s.height = height;
                return s;
            },
            py::arg("base"), py::arg("axis"), py::arg("radius"), py::arg("height"),
            "Capped cylinder from base along axis for height.")
        .def_static(
            "mesh",
            [](const py::handle& file, const py::handle& scale, const Vec3& rotation,
               const Vec3& translation) {
                SolidDescription s = solid(Kind::Mesh);
                s.file = pathFrom(file);
                s.transform = {scaleFrom(scale), rotation, translation};
                return s;
            },
            py::arg("file"), py::arg("scale") = 1.0f, py::arg("rotation") = Vec3{},
            py::arg("translation") = Vec3{},
            "A triangle mesh from an OBJ file (a relative path is relative to the working "
            "directory), placed by scale, rotation (degrees) and translation.")
        .def_property(
            "kind", [](const SolidDescription& s) { return kindName(s.kind); },
            [](SolidDescription& s, const std::string& name) { s.kind = parseKind(name); },
            "box, sphere, plane, cylinder or mesh")
        // A box's corners are "min" and "max" as in scene files (an attribute
        // named "box" would hide the box() factory).
        .def_property(
            "min", [](const SolidDescription& s) { return s.box.min; },
            [](SolidDescription& s, const Vec3& v) { s.box.min = v; }, "box")
        .def_property(
            "max", [](const SolidDescription& s) { return s.box.max; },
            [](SolidDescription& s, const Vec3& v) { s.box.max = v; }, "box")
        .def_readwrite("center", &SolidDescription::center)
        .def_property("radius", floatGetter(&SolidDescription::radius),
                      floatSetter(&SolidDescription::radius))
        .def_readwrite("point", &SolidDescription::point)
        .def_readwrite("normal", &SolidDescription::normal)
        .def_readwrite("base", &SolidDescription::base)
        .def_readwrite("axis", &SolidDescription::axis)
        .def_property("height", floatGetter(&SolidDescription::height),
                      floatSetter(&SolidDescription::height))
        .def_readwrite("file", &SolidDescription::file)
        .def_readwrite("transform", &SolidDescription::transform)
        .def_property("adhesion", floatGetter(&SolidDescription::adhesion),
                      floatSetter(&SolidDescription::adhesion),
                      "wetting with surface tension: work of adhesion / 2 sigma, [0, 1]")
        .def_readwrite("motion", &SolidDescription::motion,
                       "a prescribed motion (pbf.Motion); none by default")
        .def_readwrite("field", &SolidDescription::field, "name in messages, e.g. \"solids[2]\"")
        .def("__repr__", [](const py::object& self) {
            switch (self.cast<const SolidDescription&>().kind) {
                case Kind::Box:
                    return reprOf(self, "SolidDescription.box", {"min", "max"});
                case Kind::Sphere:
                    return reprOf(self, "SolidDescription.sphere", {"center", "radius"});
                case Kind::Plane:
                    return reprOf(self, "SolidDescription.plane", {"point", "normal"});
                case Kind::Cylinder:
                    return reprOf(self, "SolidDescription.cylinder",
                                  {"base", "axis", "radius", "height"});
                case Kind::Mesh:
                    return reprOf(self, "SolidDescription.mesh", {"file", "transform"});
            }
            return std::string("SolidDescription()");
        });
}

void bindEmitters(py::module_& m) {
    const EmitterDescription defaults;
    py::class_<EmitterDescription>(
        m, "EmitterDescription",
        "A nozzle pouring water: discs of particles leave `position` along `direction` at "
        "`speed` between `start` and `end` seconds or until `max_particles` were emitted.")
        .def(py::init([](const Vec3& position, const Vec3& direction, float radius, float speed,
                         float start, float end, std::size_t maxParticles, float width,
                         float height, float flowRate) {
                 EmitterDescription e;
                 e.position = position;
                 e.direction = direction;
                 e.radius = radius;
                 e.speed = speed;
                 e.width = width;
                 e.height = height;
                 e.flowRate = flowRate;
                 e.start = start;
                 e.end = end;
                 e.maxParticles = maxParticles;
                 return e;
             }),
             py::arg("position"), py::arg("direction") = defaults.direction,
             py::arg("radius") = defaults.radius, py::arg("speed") = defaults.speed,
             py::arg("start") = defaults.start, py::arg("end") = defaults.end,
             py::arg("max_particles") = defaults.maxParticles, py::arg("width") = defaults.width,
             py::arg("height") = defaults.height, py::arg("flow_rate") = defaults.flowRate)
        .def_readwrite("position", &EmitterDescription::position, "metres")
        .def_readwrite("direction", &EmitterDescription::direction)
        .def_property("radius", floatGetter(&EmitterDescription::radius),
                      floatSetter(&EmitterDescription::radius), "m, [particle radius, domain size]")
        .def_property("speed", floatGetter(&EmitterDescription::speed),
                      floatSetter(&EmitterDescription::speed), "m/s, (0, 100]")
        .def_property("start", floatGetter(&EmitterDescription::start),
                      floatSetter(&EmitterDescription::start), "s, >= 0")
        .def_property("end", floatGetter(&EmitterDescription::end),
                      floatSetter(&EmitterDescription::end), "s, > start")
        .def_readwrite("max_particles", &EmitterDescription::maxParticles, "0: no budget")
        .def_property("width", floatGetter(&EmitterDescription::width),
                      floatSetter(&EmitterDescription::width),
                      "m; with height > 0: a rectangular nozzle instead of the disc")
        .def_property("height", floatGetter(&EmitterDescription::height),
                      floatSetter(&EmitterDescription::height), "m")
        .def_property("flow_rate", floatGetter(&EmitterDescription::flowRate),
                      floatSetter(&EmitterDescription::flowRate),
                      "m^3/s; > 0: sets the speed (instead of `speed`)")
        .def_readwrite("field", &EmitterDescription::field,
                       "name in messages, e.g. \"emitters[0]\"")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "EmitterDescription",
                          {"position", "direction", "radius", "width", "height", "speed",
                           "flow_rate", "start", "end", "max_particles"});
        });
}

void bindOutlets(py::module_& m) {
    py::class_<OutletDescription>(
        m, "OutletDescription",
        "Where water leaves the simulation: a box, or the side of a plane its normal points to "
        "(docs/scenes.md, \"outlets\").")
        .def_static(
            "box",
            [](const Vec3& min, const Vec3& max) {
                OutletDescription o;
                o.region.kind = OutletRegion::Kind::Box;
                o.region.box = {min, max};
                return o;
            },
            py::arg("min"), py::arg("max"))
        .def_static(
            "plane",
            [](const Vec3& point, const Vec3& normal) {
                OutletDescription o;
                o.region.kind = OutletRegion::Kind::HalfSpace;
                o.region.point = point;
                const float n = length(normal);
                o.region.normal = n > 0.0f ? normal * (1.0f / n) : normal;  // 0: validate() says
                return o;
            },
            py::arg("point"), py::arg("normal"))
        .def_property_readonly("type",
                               [](const OutletDescription& o) {
                                   return o.region.kind == OutletRegion::Kind::Box ? "box"
                                                                                   : "plane";
                               })
        .def_property_readonly("min", [](const OutletDescription& o) { return o.region.box.min; })
        .def_property_readonly("max", [](const OutletDescription& o) { return o.region.box.max; })
        .def_property_readonly("point", [](const OutletDescription& o) { return o.region.point; })
        .def_property_readonly("normal", [](const OutletDescription& o) { return o.region.normal; })
        .def("__repr__", [](const py::object& self) {
            const bool box =
                self.cast<const OutletDescription&>().region.kind == OutletRegion::Kind::Box;
            return reprOf(self, "OutletDescription",
                          box ? std::initializer_list<const char*>{"type", "min", "max"}
                              : std::initializer_list<const char*>{"type", "point", "normal"});
        });
}

// Replaces `target` by the Python list `items` when one was given.
template <class T>
void assignIfGiven(std::vector<T>& target, const py::handle& items) {
    if (!items.is_none()) target = items.cast<std::vector<T>>();
}

void bindWorldDef(py::module_& m) {
    const auto listRepr = [](const py::object& self) {
        return py::repr(py::list(self)).cast<std::string>();
    };
    py::bind_vector<std::vector<FluidBlock>>(m, "FluidBlockList").def("__repr__", listRepr);
    py::bind_vector<std::vector<SolidDescription>>(m, "SolidList").def("__repr__", listRepr);
    py::bind_vector<std::vector<EmitterDescription>>(m, "EmitterList").def("__repr__", listRepr);
    py::bind_vector<std::vector<OutletDescription>>(m, "OutletList").def("__repr__", listRepr);
    py::bind_vector<std::vector<RigidBodyDescription>>(m, "RigidBodyList")
        .def("__repr__", listRepr);
    // Plain Python lists assign to the definition's lists.
    py::implicitly_convertible<py::list, std::vector<FluidBlock>>();
    py::implicitly_convertible<py::list, std::vector<SolidDescription>>();
    py::implicitly_convertible<py::list, std::vector<EmitterDescription>>();
    py::implicitly_convertible<py::list, std::vector<OutletDescription>>();
    py::implicitly_convertible<py::list, std::vector<RigidBodyDescription>>();

    py::class_<WorldDef>(m, "WorldDef",
                         "The definition of a simulation: parameters, fluid blocks, solids, "
                         "emitters, frame rate and state guard (include/pbf/world/world_def.hpp).")
        .def(py::init([](const std::string& name, const py::handle& simulation,
                         const py::handle& blocks, const py::handle& solids,
                         const py::handle& emitters, float fps, const py::handle& guard) {
                 WorldDef d;
                 d.name = name;
                 if (!simulation.is_none()) d.simulation = simulation.cast<SimulationParams>();
                 assignIfGiven(d.fluidBlocks, blocks);
                 assignIfGiven(d.solids, solids);
                 assignIfGiven(d.emitters, emitters);
                 d.fps = fps;
                 if (!guard.is_none()) d.guard = guard.cast<GuardParams>();
                 return d;
             }),
             py::arg("name") = WorldDef{}.name, py::arg("simulation") = py::none(),
             py::arg("fluid_blocks") = py::none(), py::arg("solids") = py::none(),
             py::arg("emitters") = py::none(), py::arg("fps") = WorldDef{}.fps,
             py::arg("guard") = py::none())
        .def_readwrite("name", &WorldDef::name)
        .def_readwrite("simulation", &WorldDef::simulation)
        .def_readwrite("fluid_blocks", &WorldDef::fluidBlocks)
        .def_readwrite("solids", &WorldDef::solids)
        .def_readwrite("emitters", &WorldDef::emitters)
        .def_readwrite("outlets", &WorldDef::outlets,
                       "pbf.OutletDescription list (docs/scenes.md, \"outlets\")")
        .def_readwrite("rigid_bodies", &WorldDef::rigidBodies,
                       "pbf.RigidBodyDescription list (docs/scenes.md, \"rigid_bodies\")")
        .def_property("fps", floatGetter(&WorldDef::fps), floatSetter(&WorldDef::fps),
                      "frames per simulated second, (0, 1e4]")
        .def_readwrite("guard", &WorldDef::guard)
        .def_readwrite("source", &WorldDef::source, "the scene file it came from, or \"\"")
        .def(
            "validate", [](const WorldDef& d) { return validate(d); },
            "\"\" when valid, else \"field: problem\" for the first invalid field.")
        .def(
            "count_particles", [](const WorldDef& d) { return countParticles(d); },
            "Particles the fluid blocks create (before solids remove any).")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "WorldDef",
                          {"name", "simulation", "fluid_blocks", "solids", "rigid_bodies",
                           "emitters", "outlets", "fps", "guard"});
        });
}

void bindScene(py::module_& m) {
    const OutputParams defaults;
    py::class_<OutputParams>(m, "OutputParams", "What pbf.run / `pbf run` writes.")
        .def(py::init<>())
        .def_readwrite("frames", &OutputParams::frames, "frames to simulate, [1, 1e6]")
        .def_readwrite("directory", &OutputParams::directory)
        .def_readwrite("particles", &OutputParams::writeParticles, "binary PLY per frame")
        .def_readwrite("vdb_points", &OutputParams::writeVdbPoints)
        .def_readwrite("vtk", &OutputParams::writeVtk,
                       "VTK XML particles per frame (frame_NNNNN.vtu) and particles.pvd")
        .def_readwrite("checkpoint_every", &OutputParams::checkpointEvery, "frames, 0: off")
        .def_property("checkpoint_seconds", floatGetter(&OutputParams::checkpointSeconds),
                      floatSetter(&OutputParams::checkpointSeconds), "wall-clock seconds, 0: off")
        .def_readwrite("checkpoints", &OutputParams::writeCheckpoints)
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "OutputParams",
                          {"frames", "directory", "particles", "vtk", "checkpoint_every",
                           "checkpoint_seconds", "checkpoints"});
        });

    py::class_<Scene, WorldDef>(m, "Scene",
                                "A scene file: a WorldDef plus what pbf.run writes (`output`).")
        .def(py::init([](const WorldDef& definition) {
                 Scene s;
                 static_cast<WorldDef&>(s) = definition;
                 s.output.directory = "out/" + definition.name;
                 return s;
             }),
             py::arg("definition"),
             "A scene from a definition built in code (output to out/<name>).")
        .def_readwrite("output", &Scene::output)
        .def_readonly("fingerprint", &Scene::fingerprint,
                      "hash of the document after overrides (checkpoints record it)")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "Scene", {"name", "source", "simulation", "fps", "output"});
        });

    m.def("load_scene", &loadSceneFrom, py::arg("path"), py::arg("overrides") = py::none(),
          "Reads a scene file (docs/scenes.md) with overrides as pbf run --set takes them: a dict "
          "{\"solver.iterations\": 8} or a list [\"solver.iterations=8\"]. Raises "
          "FileNotFoundError or pbf.SceneError naming the file and field.");
}

}  // namespace

void bindDefinition(py::module_& m) {
    bindMotion(m);
    bindBlocksAndGuard(m);
    bindSolids(m);
    bindBodyDescription(m);
    bindEmitters(m);
    bindOutlets(m);
    bindWorldDef(m);
    bindScene(m);
}

}  // namespace pbf::python
