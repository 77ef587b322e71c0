#include "pbf/world/emitter.hpp"

#include <algorithm>
#include <cmath>

namespace pbf {

std::vector<Vec3> emitterDisc(const EmitterDescription& e, float particleRadius) {
    const float spacing = 2.0f * particleRadius;
    const Vec3 axis = e.direction * (1.0f / length(e.direction));
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
    const float r = params.particleRadius;
    inside_ = {params.domain.min + Vec3{r, r, r}, params.domain.max - Vec3{r, r, r}};
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
