#include "pbf/solids.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "world/boundary_scale.hpp"

namespace pbf {
namespace {

Vec3 normalised(const Vec3& v) {
    const float len = length(v);
    return len > 0.0f ? v * (1.0f / len) : Vec3{0.0f, 1.0f, 0.0f};
}

std::string format(const Vec3& v) {
    std::ostringstream s;
    s << "[" << v.x << ", " << v.y << ", " << v.z << "]";
    return s.str();
}

class BoxSolid final : public Solid {
  public:
    explicit BoxSolid(const Aabb& box) : box_(box) {}
    float signedDistance(const Vec3& p, Vec3& normal) const override {
        const Vec3 centre = (box_.min + box_.max) * 0.5f;
        const Vec3 half = box_.extent() * 0.5f;
        const Vec3 q{std::fabs(p.x - centre.x) - half.x, std::fabs(p.y - centre.y) - half.y,
                     std::fabs(p.z - centre.z) - half.z};
        const Vec3 sign{p.x < centre.x ? -1.0f : 1.0f, p.y < centre.y ? -1.0f : 1.0f,
                        p.z < centre.z ? -1.0f : 1.0f};
        const Vec3 outside{std::max(q.x, 0.0f), std::max(q.y, 0.0f), std::max(q.z, 0.0f)};
        const float outsideLength = length(outside);
        if (outsideLength > 0.0f) {
            normal = normalised({outside.x * sign.x, outside.y * sign.y, outside.z * sign.z});
            return outsideLength;
        }
        // Inside: the nearest face.
        if (q.x >= q.y && q.x >= q.z) {
            normal = {sign.x, 0.0f, 0.0f};
            return q.x;
        }
        if (q.y >= q.z) {
            normal = {0.0f, sign.y, 0.0f};
            return q.y;
        }
        normal = {0.0f, 0.0f, sign.z};
        return q.z;
    }
    Aabb bounds() const override { return box_; }
    std::string describe() const override {
        return "box " + format(box_.min) + " - " + format(box_.max);
    }

  private:
    Aabb box_;
};

class SphereSolid final : public Solid {
  public:
    SphereSolid(const Vec3& c, float r) : centre_(c), radius_(r) {}
    float signedDistance(const Vec3& p, Vec3& normal) const override {
        const Vec3 d = p - centre_;
        normal = normalised(d);
        return length(d) - radius_;
    }
    Aabb bounds() const override {
        const Vec3 r{radius_, radius_, radius_};
        return {centre_ - r, centre_ + r};
    }
    std::string describe() const override {
        return "sphere at " + format(centre_) + " radius " + std::to_string(radius_);
    }

  private:
    Vec3 centre_;
    float radius_;
};

class PlaneSolid final : public Solid {
  public:
    PlaneSolid(const Vec3& point, const Vec3& normal, const Aabb& domain)
        : point_(point), normal_(normalised(normal)), domain_(domain) {}
    float signedDistance(const Vec3& p, Vec3& normal) const override {
        normal = normal_;
        return dot(p - point_, normal_);
    }
    Aabb bounds() const override { return domain_; }
    std::string describe() const override {
        return "plane through " + format(point_) + " normal " + format(normal_);
    }

  private:
    Vec3 point_;
    Vec3 normal_;
    Aabb domain_;
};

class CylinderSolid final : public Solid {
  public:
    CylinderSolid(const Vec3& base, const Vec3& axis, float radius, float height)
        : base_(base), axis_(normalised(axis)), radius_(radius), height_(height) {}
    float signedDistance(const Vec3& p, Vec3& normal) const override {
        // Exact capped-cylinder distance in (radial, axial) coordinates.
        const Vec3 d = p - base_;
        const float along = dot(d, axis_);
        const Vec3 radialVector = d - axis_ * along;
        const float radial = length(radialVector);
        const Vec3 radialDirection =
            radial > 0.0f ? radialVector * (1.0f / radial) : perpendicular();
        const float halfHeight = 0.5f * height_;
        const float qa = std::fabs(along - halfHeight) - halfHeight;  // axial
        const float qr = radial - radius_;                            // radial
        const Vec3 axialDirection = along < halfHeight ? -axis_ : axis_;
        if (qa > 0.0f && qr > 0.0f) {
            const float distance = std::sqrt(qa * qa + qr * qr);
            normal = normalised(radialDirection * qr + axialDirection * qa);
            return distance;
        }
        if (qa > qr) {
            normal = axialDirection;
            return qa;
        }
        normal = radialDirection;
        return qr;
    }
    Aabb bounds() const override {
        const Vec3 top = base_ + axis_ * height_;
        const Vec3 r{radius_, radius_, radius_};
        return {
            Vec3{std::min(base_.x, top.x), std::min(base_.y, top.y), std::min(base_.z, top.z)} - r,
            Vec3{std::max(base_.x, top.x), std::max(base_.y, top.y), std::max(base_.z, top.z)} + r};
    }
    std::string describe() const override {
        return "cylinder from " + format(base_) + " along " + format(axis_) + " radius " +
               std::to_string(radius_) + " height " + std::to_string(height_);
    }

  private:
    Vec3 perpendicular() const {
        return normalised(std::fabs(axis_.x) < 0.9f ? cross(axis_, {1, 0, 0})
                                                    : cross(axis_, {0, 1, 0}));
    }
    Vec3 base_;
    Vec3 axis_;
    float radius_;
    float height_;
};

bool within(const Aabb& box, const Vec3& p, float reach) {
    return p.x >= box.min.x - reach && p.x <= box.max.x + reach && p.y >= box.min.y - reach &&
           p.y <= box.max.y + reach && p.z >= box.min.z - reach && p.z <= box.max.z + reach;
}

Aabb worldBounds(const Aabb& local, const Pose& pose) {
    if (pose.identity()) return local;
    Aabb box{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
    for (int corner = 0; corner < 8; ++corner) {
        const Vec3 p = pose.toWorld({(corner & 1) ? local.max.x : local.min.x,
                                     (corner & 2) ? local.max.y : local.min.y,
                                     (corner & 4) ? local.max.z : local.min.z});
        box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
        box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
    }
    return box;
}

}  // namespace

void SolidSet::add(std::unique_ptr<Solid> shape, const SolidMotion& motion, bool coupled) {
    shapes_.push_back(std::move(shape));
    motions_.emplace_back();
    identity_.push_back(true);
    bounds_.emplace_back();
    coupled_.push_back(coupled);
    scales_.emplace_back();
    anyCoupled_ = anyCoupled_ || coupled;
    setMotion(shapes_.size() - 1, motion);
}

void SolidSet::setMotion(std::size_t i, const SolidMotion& motion) {
    motions_.at(i) = motion;
    identity_[i] = motion.pose.identity();
    bounds_[i] = worldBounds(shapes_[i]->bounds(), motion.pose);
    moving_ = false;
    for (const SolidMotion& m : motions_)
        moving_ = moving_ || !(m.velocity == Vec3{}) || !(m.angularVelocity == Vec3{});
}

void SolidSet::setBoundaryScale(std::size_t i, std::shared_ptr<const BoundaryScale> scale) {
    scales_.at(i) = std::move(scale);
}

float SolidSet::boundaryScale(std::size_t i, const Vec3& p) const {
    if (!scales_[i]) return 1.0f;
    return scales_[i]->at(identity_[i] ? p : motions_[i].pose.toLocal(p));
}

float SolidSet::distanceTo(std::size_t k, const Vec3& p, Vec3& normal) const {
    if (identity_[k]) return shapes_[k]->signedDistance(p, normal);
    const Pose& pose = motions_[k].pose;
    Vec3 localNormal;
    const float d = shapes_[k]->signedDistance(pose.toLocal(p), localNormal);
    normal = pose.directionToWorld(localNormal);
    return d;
}

float SolidSet::signedDistance(const Vec3& p, float reach, Vec3& normal,
                               std::size_t* nearest) const {
    float best = reach;
    for (std::size_t k = 0; k < shapes_.size(); ++k) {
        if (!within(bounds_[k], p, reach)) continue;
        Vec3 n;
        const float d = distanceTo(k, p, n);
        if (d < best) {
            best = d;
            normal = n;
            if (nearest) *nearest = k;
        }
    }
    return best;
}

std::unique_ptr<Solid> makeBoxSolid(const Aabb& box) {
    return std::make_unique<BoxSolid>(box);
}
std::unique_ptr<Solid> makeSphereSolid(const Vec3& c, float r) {
    return std::make_unique<SphereSolid>(c, r);
}
std::unique_ptr<Solid> makePlaneSolid(const Vec3& point, const Vec3& normal, const Aabb& domain) {
    return std::make_unique<PlaneSolid>(point, normal, domain);
}
std::unique_ptr<Solid> makeCylinderSolid(const Vec3& base, const Vec3& axis, float radius,
                                         float height) {
    return std::make_unique<CylinderSolid>(base, axis, radius, height);
}

}  // namespace pbf
