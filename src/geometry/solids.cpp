#include "pbf/geometry/solids.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "geometry/boundary_scale.hpp"
#include "geometry/shape_distance.hpp"

namespace pbf {
namespace {

std::string format(const Vec3& v) {
    std::ostringstream s;
    s << "[" << v.x << ", " << v.y << ", " << v.z << "]";
    return s.str();
}

class BoxSolid final : public Solid {
  public:
    explicit BoxSolid(const Aabb& box) : box_(box) {}
    float signedDistance(const Vec3& p, Vec3& normal) const override {
        return shape::boxDistance(box_, p, normal);
    }
    Aabb bounds() const override { return box_; }
    std::string describe() const override {
        return "box " + format(box_.min) + " - " + format(box_.max);
    }
    ShapeData shapeData(float, float) const override {
        ShapeData d;
        d.kind = ShapeData::Kind::Box;
        d.box = box_;
        return d;
    }

  private:
    Aabb box_;
};

class SphereSolid final : public Solid {
  public:
    SphereSolid(const Vec3& c, float r) : centre_(c), radius_(r) {}
    float signedDistance(const Vec3& p, Vec3& normal) const override {
        return shape::sphereDistance(centre_, radius_, p, normal);
    }
    Aabb bounds() const override {
        const Vec3 r{radius_, radius_, radius_};
        return {centre_ - r, centre_ + r};
    }
    std::string describe() const override {
        return "sphere at " + format(centre_) + " radius " + std::to_string(radius_);
    }
    ShapeData shapeData(float, float) const override {
        ShapeData d;
        d.kind = ShapeData::Kind::Sphere;
        d.center = centre_;
        d.radius = radius_;
        return d;
    }

  private:
    Vec3 centre_;
    float radius_;
};

class PlaneSolid final : public Solid {
  public:
    PlaneSolid(const Vec3& point, const Vec3& normal, const Aabb& domain)
        : point_(point), normal_(shape::normalised(normal)), domain_(domain) {}
    float signedDistance(const Vec3& p, Vec3& normal) const override {
        return shape::planeDistance(point_, normal_, p, normal);
    }
    Aabb bounds() const override { return domain_; }
    std::string describe() const override {
        return "plane through " + format(point_) + " normal " + format(normal_);
    }
    ShapeData shapeData(float, float) const override {
        ShapeData d;
        d.kind = ShapeData::Kind::Plane;
        d.point = point_;
        d.normal = normal_;
        return d;
    }

  private:
    Vec3 point_;
    Vec3 normal_;
    Aabb domain_;
};

class CylinderSolid final : public Solid {
  public:
    CylinderSolid(const Vec3& base, const Vec3& axis, float radius, float height)
        : base_(base), axis_(shape::normalised(axis)), radius_(radius), height_(height) {}
    float signedDistance(const Vec3& p, Vec3& normal) const override {
        return shape::cylinderDistance(base_, axis_, radius_, height_, p, normal);
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
    ShapeData shapeData(float, float) const override {
        ShapeData d;
        d.kind = ShapeData::Kind::Cylinder;
        d.base = base_;
        d.axis = axis_;
        d.radius = radius_;
        d.height = height_;
        return d;
    }

  private:
    Vec3 base_;
    Vec3 axis_;
    float radius_;
    float height_;
};

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

ShapeData Solid::shapeData(float spacing, float margin) const {
    if (!(spacing > 0.0f))
        throw std::invalid_argument("Solid::shapeData: spacing must be positive");
    const Aabb b = bounds();
    ShapeData d;
    d.kind = ShapeData::Kind::Samples;
    d.spacing = spacing;
    d.origin = b.min - Vec3{margin, margin, margin};
    const Vec3 e = b.extent() + Vec3{2.0f * margin, 2.0f * margin, 2.0f * margin};
    d.nx = int(std::ceil(e.x / spacing)) + 2;
    d.ny = int(std::ceil(e.y / spacing)) + 2;
    d.nz = int(std::ceil(e.z / spacing)) + 2;
    d.values.resize(std::size_t(d.nx) * d.ny * d.nz);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                Vec3 normal;
                d.values[(std::size_t(k) * d.ny + j) * d.nx + i] =
                    signedDistance(d.origin + Vec3{float(i), float(j), float(k)} * spacing, normal);
            }
    // Beyond the samples the solid is at least the margin away.
    d.outside = margin;
    return d;
}

void SolidSet::add(std::unique_ptr<Solid> shape, const SolidMotion& motion, bool coupled) {
    shapes_.push_back(std::move(shape));
    motions_.emplace_back();
    identity_.push_back(true);
    bounds_.emplace_back();
    coupled_.push_back(coupled);
    scales_.emplace_back();
    adhesion_.push_back(0.0f);
    index_.valid = false;
    anyCoupled_ = anyCoupled_ || coupled;
    setMotion(shapes_.size() - 1, motion);
}

void SolidSet::setMotion(std::size_t i, const SolidMotion& motion) {
    motions_.at(i) = motion;
    identity_[i] = motion.pose.identity();
    bounds_[i] = worldBounds(shapes_[i]->bounds(), motion.pose);
    index_.valid = false;  // until the next buildIndex()
    moving_ = false;
    for (const SolidMotion& m : motions_)
        moving_ = moving_ || !(m.velocity == Vec3{}) || !(m.angularVelocity == Vec3{});
}

void SolidSet::setBoundaryScale(std::size_t i, std::shared_ptr<const BoundaryScale> scale) {
    scales_.at(i) = std::move(scale);
}

void SolidSet::setAdhesion(std::size_t i, float adhesion) {
    adhesion_.at(i) = adhesion;
}

float SolidSet::boundaryScale(std::size_t i, const Vec3& p) const {
    if (!scales_[i]) return 1.0f;
    return scales_[i]->at(identity_[i] ? p : motions_[i].pose.toLocal(p));
}

float SolidSet::distanceTo(std::size_t k, const Vec3& p, Vec3& normal) const {
    return shape::posedDistance(*shapes_[k], identity_[k], motions_[k].pose, p, normal);
}

float SolidSet::signedDistance(const Vec3& p, float reach, Vec3& normal,
                               std::size_t* nearest) const {
    shape::NearestSolid best(reach);
    const auto consider = [&](std::size_t k) { best.offer(*this, k, bounds_[k], p, reach); };
    if (index_.valid && reach <= index_.margin && index_.box.contains(p)) {
        const Vec3 g = (p - index_.box.min) * index_.inverseCell;
        const int i = std::min(int(g.x), index_.nx - 1), j = std::min(int(g.y), index_.ny - 1),
                  k = std::min(int(g.z), index_.nz - 1);
        const std::size_t cell = (std::size_t(k) * index_.ny + j) * index_.nx + i;
        for (std::uint32_t m = index_.start[cell]; m < index_.start[cell + 1]; ++m)
            consider(index_.items[m]);
        return best.result(normal, nearest);
    }
    for (std::size_t k = 0; k < shapes_.size(); ++k) consider(k);
    return best.result(normal, nearest);
}

void SolidSet::buildIndex(const Aabb& box, float margin) {
    Index& x = index_;
    x.valid = false;
    // Worth it only for many solids; a few are tested faster one by one.
    if (shapes_.size() < 8 || !(margin > 0.0f)) return;
    const Vec3 e = box.extent();
    const float cell = std::max(margin, std::max(e.x, std::max(e.y, e.z)) / 128.0f);
    x.box = box;
    x.margin = margin;
    x.inverseCell = 1.0f / cell;
    x.nx = std::max(1, int(std::ceil(e.x * x.inverseCell)));
    x.ny = std::max(1, int(std::ceil(e.y * x.inverseCell)));
    x.nz = std::max(1, int(std::ceil(e.z * x.inverseCell)));
    const std::size_t cells = std::size_t(x.nx) * x.ny * x.nz;
    // Cell ranges of each solid's bounds grown by the margin, clamped to the grid.
    const auto range = [&](std::size_t k, int lo[3], int hi[3]) {
        const int n[3] = {x.nx, x.ny, x.nz};
        for (int a = 0; a < 3; ++a) {
            // Clamped as floats first: a plane's bounds are the whole domain,
            // a far solid's may be huge.
            const float l = std::clamp((bounds_[k].min[a] - margin - box.min[a]) * x.inverseCell,
                                       -1.0f, float(n[a]) + 1.0f);
            const float h = std::clamp((bounds_[k].max[a] + margin - box.min[a]) * x.inverseCell,
                                       -1.0f, float(n[a]) + 1.0f);
            if (h < 0.0f || l >= float(n[a])) return false;
            lo[a] = std::clamp(int(std::floor(l)), 0, n[a] - 1);
            hi[a] = std::clamp(int(std::floor(h)), 0, n[a] - 1);
        }
        return true;
    };
    x.start.assign(cells + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        if (pass == 1) {
            for (std::size_t c = 0; c < cells; ++c) x.start[c + 1] += x.start[c];
            x.items.resize(x.start[cells]);
        }
        std::vector<std::uint32_t> fill(pass == 1 ? x.start.begin() : x.start.end(),
                                        pass == 1 ? x.start.end() - 1 : x.start.end());
        for (std::size_t k = 0; k < shapes_.size(); ++k) {
            int lo[3], hi[3];
            if (!range(k, lo, hi)) continue;
            for (int c = lo[2]; c <= hi[2]; ++c)
                for (int b = lo[1]; b <= hi[1]; ++b)
                    for (int a = lo[0]; a <= hi[0]; ++a) {
                        const std::size_t cellIndex = (std::size_t(c) * x.ny + b) * x.nx + a;
                        if (pass == 0)
                            ++x.start[cellIndex + 1];
                        else
                            x.items[fill[cellIndex]++] = std::uint32_t(k);
                    }
        }
    }
    x.valid = true;
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
