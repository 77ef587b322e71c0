// Adapter from pbf positions to OpenVDB's particle-list concept (private
// header of pbf_surface; includes OpenVDB, keep it out of public headers).
#pragma once

#include <openvdb/openvdb.h>

#include <cstddef>
#include <span>

#include "pbf/core/vec3.hpp"

namespace pbf::surface::detail {

// What ParticlesToLevelSet, createPointIndexGrid and PointIndexIterator read.
class ParticleList {
  public:
    using PosType = openvdb::Vec3R;
    using value_type = openvdb::Vec3R;

    explicit ParticleList(std::span<const Vec3> positions) : positions_(positions) {}
    std::size_t size() const { return positions_.size(); }
    void getPos(std::size_t n, openvdb::Vec3R& xyz) const {
        const Vec3& p = positions_[n];
        xyz = openvdb::Vec3R(p.x, p.y, p.z);
    }

  private:
    std::span<const Vec3> positions_;
};

}  // namespace pbf::surface::detail
