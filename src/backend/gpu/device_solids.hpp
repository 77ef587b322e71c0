// The solids as the GPU backend's kernels see them (private header): plain
// data in device memory, with the same queries as the host's SolidSet
// (include/pbf/geometry/solids.hpp), so that backend/boundary.hpp's templates run on
// either. Analytic shapes are evaluated exactly (geometry/shape_distance.hpp,
// the functions the host's Solid classes call); meshes and any other shape
// by trilinear interpolation of their distance field sampled on a grid in
// their own frame (Solid::shapeData: a mesh gives its level set's voxels,
// so the device interpolates the same values the host does). Every solid
// is placed by its pose and moves with its motion, uploaded before every
// step; a body's boundary-density ratio grid (geometry/boundary_scale.hpp) is
// queried in the body's frame as on the host.
//
// The queries visit the solids in index order and keep the first nearest,
// as SolidSet::signedDistance does (its lookup grid changes which solids
// are tried, not the answer).
#pragma once

#include <cstddef>
#include <cstdint>

#include "geometry/shape_distance.hpp"
#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf::gpu::PBF_DEVICE_NAMESPACE {

// One shape in its own frame: ShapeData's fixed-size part, copied whole,
// and its samples in device memory.
struct DeviceShape : ShapeParameters {
    shape::GridSamples samples;  // Samples: values in device memory

    PBF_HD float signedDistance(const Vec3& p, Vec3& n) const {
        switch (kind) {
            case ShapeData::Kind::Box:
                return shape::boxDistance(box, p, n);
            case ShapeData::Kind::Sphere:
                return shape::sphereDistance(center, radius, p, n);
            case ShapeData::Kind::Plane:
                return shape::planeDistance(point, normal, p, n);
            case ShapeData::Kind::Cylinder:
                return shape::cylinderDistance(base, axis, radius, height, p, n);
            case ShapeData::Kind::Samples:
                break;
        }
        const float d = samples.distance(p, outside + offset, n);
        return d - offset;
    }
};

// The posed solids: pointers into device memory (DeviceSolidStore).
struct DeviceSolids {
    std::uint32_t count = 0;
    const DeviceShape* shapes = nullptr;
    const SolidMotion* motions = nullptr;
    const std::uint8_t* identity = nullptr;      // pose is the identity: query the shape directly
    const Aabb* bounds = nullptr;                // world-space boxes around the surfaces
    const std::uint8_t* coupled = nullptr;       // a rigid body's surface
    const shape::GridSamples* scales = nullptr;  // values null: no boundary scale
    const float* adhesions = nullptr;            // SolidSet::adhesion (surface tension)
    bool moving = false;

    PBF_HD bool anyMoving() const { return moving; }
    PBF_HD const SolidMotion& motion(std::size_t k) const { return motions[k]; }
    PBF_HD bool isCoupled(std::size_t k) const { return k < count && coupled[k] != 0; }
    PBF_HD float adhesion(std::size_t k) const { return adhesions[k]; }
    PBF_HD bool hasBoundaryScale(std::size_t k) const { return scales[k].values != nullptr; }
    PBF_HD float boundaryScale(std::size_t k, const Vec3& p) const {
        if (!scales[k].values) return 1.0f;
        return scales[k].interpolate(identity[k] ? p : motions[k].pose.toLocal(p), 1.0f);
    }

    PBF_HD float distanceTo(std::size_t k, const Vec3& p, Vec3& n) const {
        return shape::posedDistance(shapes[k], identity[k] != 0, motions[k].pose, p, n);
    }

    // SolidSet::signedDistance: the smallest signed distance over the solids
    // whose bounds lie within `reach` of p, else `reach`.
    PBF_HD float signedDistance(const Vec3& p, float reach, Vec3& n,
                                std::size_t* nearest = nullptr) const {
        shape::NearestSolid best(reach);
        for (std::uint32_t k = 0; k < count; ++k) best.offer(*this, k, bounds[k], p, reach);
        return best.result(n, nearest);
    }
};

}  // namespace pbf::gpu::PBF_DEVICE_NAMESPACE
