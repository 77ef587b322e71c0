#include "pbf/io/scene.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/hash.hpp"
#include "io/json_reader.hpp"
#include "pbf/core/param_table.hpp"
#include "pbf/io/h5part.hpp"
#include "pbf/io/motion_file.hpp"

namespace pbf {
namespace {

using detail::JsonReader;
using nlohmann::json;

// nlohmann::json parses iteratively but dumps recursively (error messages
// quote values, the fingerprint dumps the document): a scene nested 10^6
// levels deep overflowed the stack (found by fuzz/fuzz_scene). Scenes nest
// 4 levels; more than kMaxNesting is refused while parsing.
constexpr int kMaxNesting = 64;
constexpr std::size_t kMaxOverrideDepth = 16;

// True when `text` nests arrays or objects deeper than kMaxNesting (the
// parser is iterative, so checking is safe; syntax errors are left to the
// real parse).
bool nestedTooDeep(std::string_view text) {
    bool tooDeep = false;
    const json::parser_callback_t limit = [&tooDeep](int depth, json::parse_event_t, json&) {
        if (depth > kMaxNesting) tooDeep = true;
        return !tooDeep;  // discard what is too deep instead of building it
    };
    [[maybe_unused]] const json parsed =
        json::parse(text, limit, /*allow_exceptions=*/false, /*ignore_comments=*/true);
    return tooDeep;
}

// "key: " for the last key before the number quoted in nlohmann's message
// "number overflow parsing '1e999'", or "" when it cannot be found.
std::string fieldOfNumber(std::string_view text, const std::string& message) {
    const std::size_t open = message.find('\'');
    const std::size_t close = message.rfind('\'');
    if (open == std::string::npos || close <= open + 1) return {};
    const std::size_t at = text.find(message.substr(open + 1, close - open - 1));
    if (at == std::string_view::npos) return {};
    const std::size_t colon = text.rfind(':', at);
    const std::size_t end = colon == std::string_view::npos ? colon : text.rfind('"', colon);
    const std::size_t begin =
        end == std::string_view::npos || end == 0 ? end : text.rfind('"', end - 1);
    if (begin == std::string_view::npos || end == std::string_view::npos) return {};
    return std::string(text.substr(begin + 1, end - begin - 1)) + ": ";
}

void applyOverride(json& document, const SceneOverride& o, const std::string& file) {
    if (std::count(o.path.begin(), o.path.end(), '.') >=
        static_cast<std::ptrdiff_t>(kMaxOverrideDepth))
        throw SceneError(file + ": --set " + o.path.substr(0, 200) + ": more than " +
                         std::to_string(kMaxOverrideDepth) + " levels of fields");
    json* node = &document;
    std::stringstream parts(o.path);
    std::string part;
    std::string walked;
    while (std::getline(parts, part, '.')) {
        walked += (walked.empty() ? "" : ".") + part;
        if (part.empty()) throw SceneError(file + ": --set " + o.path + ": empty field name");
        if (node->is_array()) {
            std::size_t index = 0;
            try {
                index = std::stoul(part);
            } catch (const std::exception&) {
                throw SceneError(file + ": --set " + o.path + ": " + walked +
                                 " is an array; expected an index");
            }
            if (index >= node->size())
                throw SceneError(file + ": --set " + o.path + ": index " + part + " out of range");
            node = &(*node)[index];
        } else {
            if (node->is_null()) *node = json::object();
            if (!node->is_object())
                throw SceneError(file + ": --set " + o.path + ": " + walked + " is not an object");
            node = &(*node)[part];
        }
    }
    if (nestedTooDeep(o.value))
        throw SceneError(file + ": --set " + o.path + ": value nested deeper than " +
                         std::to_string(kMaxNesting) + " levels");
    // A value that is not JSON (a bare word) is taken as a string.
    try {
        *node = json::parse(o.value);
    } catch (const json::exception&) {
        *node = json(o.value);
    }
}

Aabb readBox(JsonReader& r) {
    const Aabb box{r.requiredVec3("min"), r.requiredVec3("max")};
    const Vec3 e = box.extent();
    if (!(e.x > 0 && e.y > 0 && e.z > 0)) r.fail("max", "must be greater than min on every axis");
    return box;
}

// Reads every row of the parameter table (pbf/core/param_table.hpp) from its
// place in the document — the top level, "fluid", "solver",
// "solver.artificial_pressure" — and refuses keys in those objects that are
// no parameter. Ranges are checked afterwards by validate(SimulationParams).
void readParams(JsonReader& root, SimulationParams& sim) {
    std::map<std::string, JsonReader, std::less<>> objects;
    // The reader of the object a path prefix names ("" is the document).
    auto objectAt = [&](auto& self, const std::string& prefix) -> JsonReader& {
        if (prefix.empty()) return root;
        if (auto it = objects.find(prefix); it != objects.end()) return it->second;
        const std::size_t dot = prefix.rfind('.');
        JsonReader& parent = dot == std::string::npos ? root : self(self, prefix.substr(0, dot));
        const std::string key = dot == std::string::npos ? prefix : prefix.substr(dot + 1);
        return objects.emplace(prefix, parent.object(key)).first->second;
    };
    for (const ParamInfo& param : paramTable()) {
        const std::string path(param.path);
        const std::size_t dot = path.rfind('.');
        JsonReader& r = objectAt(objectAt, dot == std::string::npos ? "" : path.substr(0, dot));
        const std::string key(param.name());
        if (param.required && !r.has(key)) {
            r.fail(key, param.type == ParamType::Box
                            ? "missing (required): {\"min\": [...], \"max\": [...]}"
                            : "missing (required), " + std::string(param.unit));
        }
        const ParamValue current = param.get(sim);
        switch (param.type) {
            case ParamType::Float:
                param.set(sim, r.number(key, std::get<float>(current)));
                break;
            case ParamType::Int:
                param.set(sim, r.integer(key, std::get<int>(current)));
                break;
            case ParamType::Vec3:
                param.set(sim, r.vec3(key, std::get<Vec3>(current)));
                break;
            case ParamType::Box: {
                JsonReader box = r.object(key);
                param.set(sim, readBox(box));
                box.finish();
                break;
            }
            case ParamType::Choice: {
                const std::string name =
                    r.string(key, std::string(timeStepName(std::get<TimeStepMode>(current))));
                try {
                    param.set(sim, parseTimeStepName(name));
                } catch (const std::invalid_argument& e) {
                    r.fail(key, e.what());
                }
                break;
            }
        }
    }
    for (const auto& [prefix, object] : objects) object.finish();
}

// Ranges, overlaps and placement are checked by validate(WorldDef).
void readFluidBlocks(JsonReader& root, Scene& scene) {
    const json& blocks = root.array("fluid_blocks");
    for (std::size_t i = 0; i < blocks.size(); ++i) {
        JsonReader r(blocks[i], "fluid_blocks[" + std::to_string(i) + "]", scene.source);
        FluidBlock block{readBox(r), r.vec3("velocity", {})};
        r.finish();
        scene.fluidBlocks.push_back(block);
    }
}

Vec3 readScale(JsonReader& r) {
    if (!r.has("scale")) return {1, 1, 1};
    // A number (uniform) or [sx, sy, sz].
    try {
        const float uniform = r.number("scale", 1.0f);
        return {uniform, uniform, uniform};
    } catch (const SceneError&) {
        return r.vec3("scale", {1, 1, 1});
    }
}

float positive(JsonReader& r, const std::string& key, float fallback, bool required = true) {
    if (required && !r.has(key)) r.fail(key, "missing (required)");
    const float value = r.number(key, fallback);
    if (!(value > 0.0f)) r.fail(key, "must be positive, got " + std::to_string(value));
    return value;
}

Vec3 direction(JsonReader& r, const std::string& key, const Vec3& fallback) {
    const Vec3 v = r.vec3(key, fallback);
    if (!(length(v) > 0.0f)) r.fail(key, "must be a non-zero vector");
    return v * (1.0f / length(v));
}

// output.render and the image fields that go with it (RenderOutput). The
// camera geometry is checked here too, so that a bad camera is reported
// with the file and field before anything runs.
void readRenderOutput(JsonReader& o, RenderOutput& render) {
    const std::string style = o.string("render", "none");
    if (style != "none" && style != "spheres" && style != "liquid")
        o.fail("render", "must be \"none\", \"spheres\" or \"liquid\", got \"" + style + "\"");
    render.style = style == "none" ? std::string() : style;
    render.color = o.string("render_color", render.color);
    if (render.color != "speed" && render.color != "density" && render.color != "flat")
        o.fail("render_color",
               "must be \"speed\", \"density\" or \"flat\", got \"" + render.color + "\"");
    if (o.has("image_size")) {
        const json& size = o.array("image_size");
        if (size.size() != 2 || !size[0].is_number_integer() || !size[1].is_number_integer())
            o.fail("image_size", "expected [width, height] in pixels, e.g. [960, 540]");
        const auto w = size[0].get<long long>(), h = size[1].get<long long>();
        if (w < 16 || w > 8192 || h < 16 || h > 8192)
            o.fail("image_size", "each side must be in [16, 8192] pixels, got [" +
                                     std::to_string(w) + ", " + std::to_string(h) + "]");
        render.width = static_cast<int>(w);
        render.height = static_cast<int>(h);
    }
    if (o.has("camera_position")) render.cameraPosition = o.vec3("camera_position", {});
    if (o.has("camera_target")) render.cameraTarget = o.vec3("camera_target", {});
    render.fov = o.number("camera_fov", render.fov);
    if (!(render.fov >= 1.0f && render.fov <= 170.0f))
        o.fail("camera_fov", "must be in [1, 170] degrees, got " + std::to_string(render.fov));
    if (render.cameraPosition && render.cameraTarget) {
        const Vec3 view = *render.cameraTarget - *render.cameraPosition;
        if (!(length(view) > 0.0f))
            o.fail("camera_position", "must differ from output.camera_target");
        // The renderer's up axis is +y: a vertical view has no defined roll.
        if (std::fabs(view.y) > 0.9999f * length(view))
            o.fail("camera_position", "the view direction must not be vertical (up is +y)");
    }
}

// The shape fields shared by `solids` and `rigid_bodies` (docs/scenes.md).
// Bodies have no planes; a body box may be rotated about its centre.
void readShape(JsonReader& r, SolidDescription& d, const std::filesystem::path& folder, bool body) {
    const std::string type = r.string("type", "");
    d.adhesion = r.number("adhesion", d.adhesion);  // its range: validate(WorldDef)
    if (type == "box") {
        d.kind = SolidDescription::Kind::Box;
        d.box = readBox(r);
        if (body) d.transform.rotationDegrees = r.vec3("rotation", {});
    } else if (type == "sphere") {
        d.kind = SolidDescription::Kind::Sphere;
        d.center = r.requiredVec3("center");
        d.radius = positive(r, "radius", 0.0f);
    } else if (type == "plane" && !body) {
        d.kind = SolidDescription::Kind::Plane;
        d.point = r.requiredVec3("point");
        d.normal = direction(r, "normal", {0, 1, 0});
    } else if (type == "cylinder") {
        d.kind = SolidDescription::Kind::Cylinder;
        d.base = r.requiredVec3("base");
        d.axis = direction(r, "axis", {0, 1, 0});
        d.radius = positive(r, "radius", 0.0f);
        d.height = positive(r, "height", 0.0f);
    } else if (type == "mesh") {
        d.kind = SolidDescription::Kind::Mesh;
        const std::string file = r.string("file", "");
        if (file.empty()) r.fail("file", "missing (required): path of an OBJ file");
        d.file = std::filesystem::path(file).is_absolute() ? file : (folder / file).string();
        d.transform.scale = readScale(r);
        if (!(d.transform.scale.x > 0 && d.transform.scale.y > 0 && d.transform.scale.z > 0))
            r.fail("scale", "must be positive");
        d.transform.rotationDegrees = r.vec3("rotation", {});
        d.transform.translation = r.vec3("translation", {});
    } else if (body) {
        r.fail("type",
               "expected \"box\", \"sphere\", \"cylinder\" or \"mesh\", got \"" + type + "\"");
    } else {
        r.fail("type", "expected \"box\", \"sphere\", \"plane\", \"cylinder\" or \"mesh\", got \"" +
                           type + "\"");
    }
}

// A solid's "motion" (docs/scenes.md, "Moving solids"); ranges are checked
// by validate(WorldDef).
PrescribedMotion readMotion(JsonReader& solid, const std::filesystem::path& folder) {
    PrescribedMotion m;
    if (!solid.has("motion")) return m;
    JsonReader r = solid.object("motion");
    const std::string type = r.string("type", "");
    if (r.has("pivot")) {
        m.hasPivot = true;
        m.pivot = r.requiredVec3("pivot");
    }
    if (type == "oscillate") {
        m.kind = PrescribedMotion::Kind::Oscillate;
        m.amplitude = r.vec3("amplitude", {});
        m.angleAmplitude = r.number("angle_amplitude", 0.0f);
        m.axis = r.vec3("axis", m.axis);
        m.period = r.number("period", 0.0f);
        m.phaseDegrees = r.number("phase", 0.0f);
    } else if (type == "rotate") {
        m.kind = PrescribedMotion::Kind::Rotate;
        m.axis = r.vec3("axis", m.axis);
        m.speedDegrees = r.number("speed", 0.0f);
    } else if (type == "piston" || type == "flap") {
        m.kind = type == "piston" ? PrescribedMotion::Kind::Piston : PrescribedMotion::Kind::Flap;
        m.waveHeight = r.number("wave_height", 0.0f);
        m.period = r.number("period", 0.0f);
        m.depth = r.number("depth", 0.0f);
        m.direction = r.vec3("direction", m.direction);
        m.ramp = r.number("ramp", m.ramp);
    } else if (type == "keyframes") {
        m.kind = PrescribedMotion::Kind::Keyframes;
        const bool inFile = r.has("file"), inline_ = r.has("keys");
        if (inFile == inline_)
            r.fail("keys", "give the keyframes either as keys (an array) or in a CSV file (file)");
        if (inFile) {
            const std::string file = r.string("file", "");
            m.source = std::filesystem::path(file).is_absolute() ? file : (folder / file).string();
            m.keys = readMotionCsv(m.source, r.field("file"));
        } else {
            const nlohmann::json& keys = r.array("keys");
            for (std::size_t k = 0; k < keys.size(); ++k) {
                JsonReader key(keys[k], r.field("keys") + "[" + std::to_string(k) + "]",
                               solid.file());
                if (!key.has("time")) key.fail("time", "missing (required), s");
                MotionKey mk;
                mk.time = key.number("time", 0.0f);
                mk.position = key.vec3("position", {});
                mk.rotationDegrees = key.vec3("rotation", {});
                key.finish();
                m.keys.push_back(mk);
            }
        }
    } else {
        r.fail("type",
               "expected \"oscillate\", \"rotate\", \"keyframes\", \"piston\" or "
               "\"flap\", got \"" +
                   type + "\"");
    }
    r.finish();
    return m;
}

void readSolids(JsonReader& root, Scene& scene) {
    const json& solids = root.array("solids");
    const std::filesystem::path folder = std::filesystem::path(scene.source).parent_path();
    for (std::size_t i = 0; i < solids.size(); ++i) {
        SolidDescription d;
        d.field = "solids[" + std::to_string(i) + "]";
        JsonReader r(solids[i], d.field, scene.source);
        readShape(r, d, folder, false);
        d.motion = readMotion(r, folder);
        r.finish();
        scene.solids.push_back(d);
    }
}

// Ranges (density, friction, ...) are checked by validate(WorldDef); here
// the types, the shape and that exactly one of density and mass is given.
void readRigidBodies(JsonReader& root, Scene& scene) {
    const json& bodies = root.array("rigid_bodies");
    const std::filesystem::path folder = std::filesystem::path(scene.source).parent_path();
    for (std::size_t i = 0; i < bodies.size(); ++i) {
        RigidBodyDescription b;
        b.field = "rigid_bodies[" + std::to_string(i) + "]";
        b.shape.field = b.field;
        JsonReader r(bodies[i], b.field, scene.source);
        readShape(r, b.shape, folder, true);
        if (r.has("density") == r.has("mass"))
            r.fail("density", "give exactly one of density (kg/m^3) and mass (kg)");
        if (r.has("density")) {
            b.density = r.number("density", 0.0f);
            if (!(b.density > 0.0f))
                r.fail("density", "must be positive, got " + std::to_string(b.density));
        } else {
            b.mass = r.number("mass", 0.0f);
            if (!(b.mass > 0.0f)) r.fail("mass", "must be positive, got " + std::to_string(b.mass));
        }
        b.velocity = r.vec3("velocity", {});
        b.angularVelocity = r.vec3("angular_velocity", {});
        b.friction = r.number("friction", b.friction);
        b.restitution = r.number("restitution", b.restitution);
        r.finish();
        scene.rigidBodies.push_back(b);
    }
}

void readEmitters(JsonReader& root, Scene& scene) {
    const json& emitters = root.array("emitters");
    for (std::size_t i = 0; i < emitters.size(); ++i) {
        EmitterDescription e;
        e.field = "emitters[" + std::to_string(i) + "]";
        JsonReader r(emitters[i], e.field, scene.source);
        e.position = r.requiredVec3("position");
        e.direction = direction(r, "direction", e.direction);
        // A disc of `radius`, or a `width` x `height` rectangle (an inlet).
        if (r.has("width") || r.has("height")) {
            if (r.has("radius")) r.fail("radius", "give either radius or width and height");
            e.width = positive(r, "width", 0.0f);
            e.height = positive(r, "height", 0.0f);
        } else {
            e.radius = positive(r, "radius", 0.0f);
        }
        // A stream speed, or a flow rate the speed follows from.
        if (r.has("flow_rate")) {
            if (r.has("speed")) r.fail("speed", "give either speed or flow_rate");
            e.flowRate = positive(r, "flow_rate", 0.0f);
        } else {
            e.speed = positive(r, "speed", 0.0f);
        }
        e.start = r.number("start", 0.0f);
        e.end = r.number("end", e.end);
        const int budget = r.integer("max_particles", 0);
        if (budget < 0) r.fail("max_particles", "must be >= 0 (0: no budget)");
        e.maxParticles = static_cast<std::size_t>(budget);
        r.finish();
        scene.emitters.push_back(e);
    }
}

// Outlets: {"type": "box", "min", "max"} or {"type": "plane", "point",
// "normal"} (the side the normal points to is the outlet).
void readOutlets(JsonReader& root, Scene& scene) {
    const json& outlets = root.array("outlets");
    for (std::size_t i = 0; i < outlets.size(); ++i) {
        OutletDescription o;
        o.field = "outlets[" + std::to_string(i) + "]";
        JsonReader r(outlets[i], o.field, scene.source);
        const std::string type = r.string("type", "");
        if (type == "box") {
            o.region.kind = OutletRegion::Kind::Box;
            o.region.box = readBox(r);
        } else if (type == "plane") {
            o.region.kind = OutletRegion::Kind::HalfSpace;
            o.region.point = r.requiredVec3("point");
            const Vec3 normal = r.requiredVec3("normal");
            if (!(length(normal) > 0.0f) || !std::isfinite(length(normal)))
                r.fail("normal", "must be a non-zero vector");
            o.region.normal = normal * (1.0f / length(normal));
        } else {
            r.fail("type", "expected \"box\" or \"plane\", got \"" + type + "\"");
        }
        r.finish();
        scene.outlets.push_back(o);
    }
}

// The fingerprint covers everything that shapes the simulated states. The
// document is hashed as nlohmann::json dumps it (keys sorted, numbers
// normalised), so formatting and key order do not matter, and fields added
// to the format later are covered without changes here.
std::uint64_t fingerprintOf(json document) {
    document.erase("name");
    document.erase("guard");  // stops a run, never changes a state
    if (auto out = document.find("output"); out != document.end() && out->is_object()) {
        json kept = json::object();
        if (out->contains("fps")) kept["fps"] = (*out)["fps"];  // the frame length
        if (kept.empty())
            document.erase(out);
        else
            *out = kept;
    }
    return detail::fnv1a64(document.dump(-1, ' ', false, json::error_handler_t::replace));
}

std::string defaultName(const std::string& source) {
    const std::string stem = std::filesystem::path(source).stem().string();
    return stem.empty() ? "scene" : stem;
}

}  // namespace

SceneOverride parseOverride(std::string_view assignment) {
    const std::size_t eq = assignment.find('=');
    if (eq == std::string_view::npos || eq == 0)
        throw SceneError("--set " + std::string(assignment) +
                         ": expected FIELD=VALUE, e.g. solver.iterations=8");
    return {std::string(assignment.substr(0, eq)), std::string(assignment.substr(eq + 1))};
}

Scene parseScene(std::string_view jsonText, const std::string& sourceName,
                 const std::vector<SceneOverride>& overrides) {
    if (nestedTooDeep(jsonText))
        throw SceneError(sourceName + ": JSON nested deeper than " + std::to_string(kMaxNesting) +
                         " levels (a scene needs 4)");
    json document =
        json::parse(jsonText, nullptr, /*allow_exceptions=*/false, /*ignore_comments=*/true);
    if (document.is_discarded()) {
        // Parse again with exceptions for the position of the error.
        try {
            document = json::parse(jsonText, nullptr, true, true);
        } catch (const json::out_of_range& e) {
            // A number beyond double, e.g. 1e999: nlohmann throws out_of_range,
            // not parse_error (an uncaught exception found by fuzz/fuzz_scene).
            throw SceneError(sourceName + ": " + fieldOfNumber(jsonText, e.what()) +
                             "number out of range (" + e.what() + ")");
        } catch (const json::exception& e) {
            throw SceneError(sourceName + ": not valid JSON: " + e.what());
        }
    }
    for (const SceneOverride& o : overrides) applyOverride(document, o, sourceName);

    Scene scene;
    scene.source = sourceName;
    scene.overrides = overrides;
    JsonReader root(document, "", scene.source);
    scene.name = root.string("name", defaultName(sourceName));
    if (scene.name.empty() || scene.name.find('/') != std::string::npos)
        root.fail("name", "must be a non-empty name without '/'");

    SimulationParams& sim = scene.simulation;
    readParams(root, sim);
    if (const std::string problem = validate(sim); !problem.empty())
        throw SceneError(sourceName + ": " + problem);

    {
        JsonReader o = root.object("output");
        OutputParams& out = scene.output;
        scene.fps = o.number("fps", scene.fps);
        out.frames = o.integer("frames", out.frames);
        if (out.frames < 1 || out.frames > 1000000) o.fail("frames", "must be in [1, 1000000]");
        out.directory = o.string("directory", "out/" + scene.name);
        if (out.directory.empty()) o.fail("directory", "must not be empty");
        out.writeParticles = o.boolean("particles", out.writeParticles);
        out.writeVdbPoints = o.boolean("vdb_points", out.writeVdbPoints);
        out.writeVtk = o.boolean("vtk", out.writeVtk);
        out.writeH5Part = o.boolean("h5part", out.writeH5Part);
        if (out.writeH5Part && !h5partBuilt())
            o.fail("h5part",
                   "this pbf was built without parallel HDF5 (PBF_HDF5=OFF); install "
                   "libhdf5-openmpi-dev and reconfigure, or set it to false");
        out.writeUsd = o.boolean("usd", out.writeUsd);
        out.checkpointEvery = o.integer("checkpoint_every", out.checkpointEvery);
        if (out.checkpointEvery < 0 || out.checkpointEvery > 1000000)
            o.fail("checkpoint_every", "must be in [0, 1000000] frames (0: off)");
        out.checkpointSeconds = o.number("checkpoint_seconds", out.checkpointSeconds);
        if (!(out.checkpointSeconds >= 0.0f && out.checkpointSeconds <= 1e6f))
            o.fail("checkpoint_seconds", "must be in [0, 1000000] seconds (0: off)");
        out.writeCheckpoints = o.boolean("checkpoints", out.writeCheckpoints);
        readRenderOutput(o, out.render);
        for (const char* moved : {"max_speed", "max_speed_factor"})
            if (o.has(moved))
                o.fail(moved, std::string("moved to guard.") + moved +
                                  " (the state guard is not an output setting)");
        o.finish();
    }
    {
        JsonReader g = root.object("guard");
        scene.guard.maxSpeed = g.number("max_speed", scene.guard.maxSpeed);
        scene.guard.maxSpeedFactor = g.number("max_speed_factor", scene.guard.maxSpeedFactor);
        g.finish();
    }
    readSolids(root, scene);
    readRigidBodies(root, scene);
    readEmitters(root, scene);
    readOutlets(root, scene);
    readFluidBlocks(root, scene);
    root.finish();
    if (const std::string problem = validate(static_cast<const WorldDef&>(scene)); !problem.empty())
        throw SceneError(sourceName + ": " + problem);
    scene.fingerprint = fingerprintOf(std::move(document));
    return scene;
}

Scene loadScene(const std::filesystem::path& file, const std::vector<SceneOverride>& overrides) {
    const std::string name = file.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw SceneError(
            name + ": cannot open scene file (" +
            (std::filesystem::exists(file, ec) ? "not a regular file" : "no such file") + ")");
    // Scenes are small; anything over 64 MiB is not a scene.
    if (std::filesystem::file_size(file, ec) > (std::uintmax_t{64} << 20))
        throw SceneError(name + ": scene file larger than 64 MiB");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw SceneError(name + ": cannot read scene file");
    std::ostringstream text;
    text << in.rdbuf();
    return parseScene(text.str(), name, overrides);
}

}  // namespace pbf
