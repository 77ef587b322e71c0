#include "pbf/world/emitter.hpp"

#include <algorithm>
#include <cmath>

namespace pbf {

namespace {

// A rectangle's columns: n = floor(extent / spacing) (at least one) sites
// centred on the axis, so a nozzle as wide as a channel fills it.
std::vector<float> rowOffsets(float extent, float spacing) {
    const int n = std::max(1, static_cast<int>(std::floor(extent / spacing + 1e-4f)));
    std::vector<float> offsets;
    for (int i = 0; i < n; ++i) offsets.push_back((float(i) - 0.5f * float(n - 1)) * spacing);
    return offsets;
}

// A rectangular nozzle's axes: `across` level and across the stream, `rise`
// across it in the stream's vertical plane (along x and z for a vertical
// stream).
struct RectangleAxes {
    Vec3 across, rise;
};
RectangleAxes rectangleAxes(const Vec3& axis) {
    const Vec3 up{0, 1, 0};
    Vec3 across = cross(up, axis);
    if (length(across) < 1e-6f) across = {1, 0, 0};  // a vertical stream
    across *= 1.0f / length(across);
    return {across, cross(axis, across)};
}

}  // namespace

std::vector<Vec3> emitterDisc(const EmitterDescription& e, float particleRadius) {
    const float spacing = 2.0f * particleRadius;
    const Vec3 axis = e.direction * (1.0f / length(e.direction));
    if (e.width > 0.0f && e.height > 0.0f) {
        // Width level and across the stream; height across it, upward.
        const RectangleAxes r = rectangleAxes(axis);
        std::vector<Vec3> rectangle;
        for (const float a : rowOffsets(e.height, spacing))
            for (const float b : rowOffsets(e.width, spacing))
                rectangle.push_back(r.across * b + r.rise * a);
        return rectangle;
    }
    const Vec3 helper = std::fabs(axis.x) < 0.9f ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    Vec3 u = cross(axis, helper);
    u *= 1.0f / length(u);
    const Vec3 w = cross(axis, u);
    const int reach = static_cast<int>(std::floor(e.radius / spacing));
    std::vector<Vec3> disc;
    for (int i = -reach; i <= reach; ++i)
        for (int j = -reach; j <= reach; ++j) {
            const Vec3 offset = u * (float(i) * spacing) + w * (float(j) * spacing);
            if (length(offset) <= e.radius) disc.push_back(offset);
        }
    return disc;
}

Emitter::Emitter(const EmitterDescription& description, const SimulationParams& params)
    : description_(description),
      disc_(emitterDisc(description, params.particleRadius)),
      particleRadius_(params.particleRadius),
      spacing_(params.particleSpacing()) {
    description_.direction = description.direction * (1.0f / length(description.direction));
    if (description.flowRate > 0.0f)
        description_.speed = flowSpeed(description, params.particleRadius);
    const float r = params.particleRadius;
    inside_ = {params.domain.min + Vec3{r, r, r}, params.domain.max - Vec3{r, r, r}};
}

float flowSpeed(const EmitterDescription& e, float particleRadius) {
    const double spacing = 2.0 * double(particleRadius);
    const double area = double(emitterDisc(e, particleRadius).size()) * spacing * spacing;
    return float(double(e.flowRate) / area);
}

bool Emitter::open(double time) const {
    const EmitterDescription& e = description_;
    return time >= double(e.start) && time < double(e.end) &&
           (e.maxParticles == 0 || emitted_ < e.maxParticles);
}

InletBuffer Emitter::buffer(float reach) const {
    const EmitterDescription& e = description_;
    InletBuffer b;
    b.origin = e.position;
    b.axis = e.direction;
    b.behind = particleRadius_;
    b.ahead = reach;
    b.velocity = velocity();
    if (e.width > 0.0f && e.height > 0.0f) {
        // The disc's own axes (emitterDisc): its extent along each, plus r.
        const RectangleAxes r = rectangleAxes(b.axis);
        b.across = r.across;
        b.rise = r.rise;
        for (const Vec3& offset : disc_) {
            b.halfWidth = std::max(b.halfWidth, std::fabs(dot(offset, b.across)));
            b.halfHeight = std::max(b.halfHeight, std::fabs(dot(offset, b.rise)));
        }
        b.halfWidth += particleRadius_;
        b.halfHeight += particleRadius_;
    } else {
        b.radius = e.radius + particleRadius_;
    }
    return b;
}

double Emitter::rate() const {
    return double(disc_.size()) * description_.speed / spacing_;
}

void Emitter::emit(double time, double dt, const SolidSet* solids, std::vector<Vec3>& positions) {
    const EmitterDescription& e = description_;
    const double from = std::max(time, double(e.start));
    const double to = std::min(time + dt, double(e.end));
    if (to <= from) return;
    travelled_ += e.speed * (to - from);
    while (travelled_ >= spacing_) {
        if (e.maxParticles > 0 && emitted_ >= e.maxParticles) return;
        travelled_ -= spacing_;
        // The disc left the nozzle `travelled_` metres ago.
        const Vec3 centre = e.position + e.direction * static_cast<float>(travelled_);
        for (const Vec3& offset : disc_) {
            if (e.maxParticles > 0 && emitted_ >= e.maxParticles) return;
            const Vec3 x = centre + offset;
            Vec3 normal;
            if (!inside_.contains(x)) continue;
            if (solids && solids->signedDistance(x, particleRadius_, normal) < particleRadius_)
                continue;
            positions.push_back(x);
            ++emitted_;
        }
    }
}

}  // namespace pbf
