#include "pbf/world/local_frame.hpp"

#include <algorithm>
#include <cmath>

#include "pbf/world/world_def.hpp"

namespace pbf {

namespace {

// A domain whose farthest coordinate is at most this many of its largest
// extents from the origin stays where it is: measuring from its centre would
// gain at most a few bits, and would change every scene's results near the
// origin.
constexpr double kNearOrigin = 4.0;

float shift(float value, float by) {
    return static_cast<float>(double(value) - double(by));
}

}  // namespace

Vec3 LocalFrame::toFrame(const Vec3& world) const {
    return {shift(world.x, origin.x), shift(world.y, origin.y), shift(world.z, origin.z)};
}

Vec3 LocalFrame::toWorld(const Vec3& local) const {
    return {shift(local.x, -origin.x), shift(local.y, -origin.y), shift(local.z, -origin.z)};
}

LocalFrame localFrame(const Aabb& domain) {
    const Vec3 e = domain.extent();
    const double extent = std::max({double(e.x), double(e.y), double(e.z)});
    double farthest = 0.0;
    for (const float c :
         {domain.min.x, domain.min.y, domain.min.z, domain.max.x, domain.max.y, domain.max.z})
        farthest = std::max(farthest, std::abs(double(c)));
    if (!(farthest > kNearOrigin * extent)) return {};
    const auto centre = [](float a, float b) {
        return static_cast<float>(std::round(0.5 * (double(a) + double(b))));
    };
    return {{centre(domain.min.x, domain.max.x), centre(domain.min.y, domain.max.y),
             centre(domain.min.z, domain.max.z)}};
}

WorldDef inFrame(const WorldDef& def, const LocalFrame& frame) {
    WorldDef local = def;
    if (!frame.shifted()) return local;
    local.simulation.domain = frame.toFrame(def.simulation.domain);
    for (FluidBlock& block : local.fluidBlocks) block.box = frame.toFrame(block.box);
    const auto place = [&](SolidDescription& s) {
        s.box = frame.toFrame(s.box);
        s.center = frame.toFrame(s.center);
        s.point = frame.toFrame(s.point);
        s.base = frame.toFrame(s.base);
        s.motion.pivot = frame.toFrame(s.motion.pivot);
        // Only a mesh's translation places it (a box body's rotation turns
        // it about its own centre).
        if (s.kind == SolidDescription::Kind::Mesh)
            s.transform.translation = frame.toFrame(s.transform.translation);
    };
    for (SolidDescription& s : local.solids) place(s);
    for (RigidBodyDescription& body : local.rigidBodies) place(body.shape);
    for (EmitterDescription& e : local.emitters) e.position = frame.toFrame(e.position);
    for (OutletDescription& o : local.outlets) {
        o.region.box = {frame.toFrame(o.region.box.min), frame.toFrame(o.region.box.max)};
        o.region.point = frame.toFrame(o.region.point);
    }
    return local;
}

}  // namespace pbf
