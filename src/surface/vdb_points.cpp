// Particle caches as OpenVDB PointDataGrids (see vdb_points.hpp).
#include "pbf/surface/vdb_points.hpp"

#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/points/PointAttribute.h>
#include <openvdb/points/PointConversion.h>
#include <openvdb/points/PointDataGrid.h>
#include <openvdb/tools/PointIndexGrid.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <vector>

#include "vdb_points_detail.hpp"

namespace pbf::surface {
namespace {

using openvdb::points::PointAttributeVector;
using openvdb::points::PointDataGrid;

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& message) {
    throw IoError(path.string() + ": " + message);
}

openvdb::Vec3f toVdb(const Vec3& v) {
    return {v.x, v.y, v.z};
}

}  // namespace

namespace detail {

void writePointsVdb(const std::filesystem::path& path, const ParticleFrame& frame,
                    const std::string& gridName, const ExtraPointAttributes& extra) {
    openvdb::initialize();
    const std::size_t n = frame.position.size();
    if ((!frame.velocity.empty() && frame.velocity.size() != n) ||
        (!frame.density.empty() && frame.density.size() != n) ||
        (!frame.id.empty() && frame.id.size() != n))
        fail(path, "particle attributes have different lengths");
    std::vector<openvdb::Vec3f> positions(n), velocities;
    std::vector<float> densities = frame.density;
    std::vector<std::int32_t> ids;
    for (std::size_t i = 0; i < n; ++i) positions[i] = toVdb(frame.position[i]);
    for (const Vec3& v : frame.velocity) velocities.push_back(toVdb(v));
    for (std::uint64_t id : frame.id) {
        // Houdini and Blender expect a signed 32-bit "id".
        if (id > std::uint64_t(std::numeric_limits<std::int32_t>::max()))
            fail(path, "particle id " + std::to_string(id) +
                           " does not fit OpenVDB points' 32-bit signed id (what Houdini and "
                           "Blender read); write VTK (output.vtk) or USD (output.usd), which "
                           "keep 64-bit ids");
        ids.push_back(static_cast<std::int32_t>(id));
    }
    for (const auto& [name, values] : extra.floats)
        if (values.size() != n) fail(path, "attribute " + name + " has the wrong length");
    for (const auto& [name, values] : extra.ints)
        if (values.size() != n) fail(path, "attribute " + name + " has the wrong length");

    const PointAttributeVector<openvdb::Vec3f> positionList(positions);
    // About 8 particles per voxel: the layout OpenVDB recommends for caches.
    const float voxelSize = n > 0 ? openvdb::points::computeVoxelSize(positionList, 8) : 0.1f;
    const openvdb::math::Transform::Ptr transform =
        openvdb::math::Transform::createLinearTransform(voxelSize);
    const auto index = openvdb::tools::createPointIndexGrid<openvdb::tools::PointIndexGrid>(
        positionList, *transform);
    PointDataGrid::Ptr grid =
        openvdb::points::createPointDataGrid<openvdb::points::NullCodec, PointDataGrid>(
            *index, positionList, *transform);
    grid->setName(gridName);
    auto& tree = grid->tree();
    if (!velocities.empty()) {
        openvdb::points::appendAttribute<openvdb::Vec3f>(tree, "v");
        openvdb::points::populateAttribute(tree, index->tree(), "v",
                                           PointAttributeVector<openvdb::Vec3f>(velocities));
    }
    if (!densities.empty()) {
        openvdb::points::appendAttribute<float>(tree, "density");
        openvdb::points::populateAttribute(tree, index->tree(), "density",
                                           PointAttributeVector<float>(densities));
    }
    if (!ids.empty()) {
        openvdb::points::appendAttribute<std::int32_t>(tree, "id");
        openvdb::points::populateAttribute(tree, index->tree(), "id",
                                           PointAttributeVector<std::int32_t>(ids));
    }
    for (const auto& [name, values] : extra.floats) {
        openvdb::points::appendAttribute<float>(tree, name);
        openvdb::points::populateAttribute(tree, index->tree(), name,
                                           PointAttributeVector<float>(values));
    }
    for (const auto& [name, values] : extra.ints) {
        openvdb::points::appendAttribute<std::int32_t>(tree, name);
        openvdb::points::populateAttribute(tree, index->tree(), name,
                                           PointAttributeVector<std::int32_t>(values));
    }
    writeFileAtomically(path, [&](std::ostream& out) {
        openvdb::io::Stream stream(out);
        stream.write(openvdb::GridCPtrVec{grid});
    });
}

}  // namespace detail

void writeParticlesVdb(const std::filesystem::path& path, const ParticleFrame& frame) {
    detail::writePointsVdb(path, frame, "points", {});
}

void writeParticlesVdb(const std::filesystem::path& path, const ParticleStore& p) {
    ParticleFrame frame;
    for (std::uint32_t i : p.orderById()) {
        frame.position.push_back(p.position.get(i));
        frame.velocity.push_back(p.velocity.get(i));
        frame.density.push_back(p.density[i]);
        frame.id.push_back(p.id[i]);
    }
    writeParticlesVdb(path, frame);
}

ParticleFrame readParticlesVdb(const std::filesystem::path& path) {
    openvdb::initialize();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        fail(path, "cannot open VDB file (no such file)");
    ParticleFrame frame;
    try {
        openvdb::io::File file(path.string());
        file.open(/*delayLoad=*/false);
        PointDataGrid::Ptr grid;
        for (const openvdb::GridBase::Ptr& g : *file.getGrids())
            if (auto points = openvdb::gridPtrCast<PointDataGrid>(g)) {
                grid = points;
                break;
            }
        file.close();
        if (!grid) fail(path, "no point data grid in the file");

        const openvdb::math::Transform& transform = grid->transform();
        for (auto leaf = grid->tree().cbeginLeaf(); leaf; ++leaf) {
            const auto& set = leaf->attributeSet();
            const bool hasV = set.find("v") != openvdb::points::AttributeSet::INVALID_POS;
            const bool hasDensity =
                set.find("density") != openvdb::points::AttributeSet::INVALID_POS;
            const bool hasId = set.find("id") != openvdb::points::AttributeSet::INVALID_POS;
            openvdb::points::AttributeHandle<openvdb::Vec3f> position(
                leaf->constAttributeArray("P"));
            std::unique_ptr<openvdb::points::AttributeHandle<openvdb::Vec3f>> velocity;
            std::unique_ptr<openvdb::points::AttributeHandle<float>> density;
            std::unique_ptr<openvdb::points::AttributeHandle<std::int32_t>> id;
            if (hasV)
                velocity = std::make_unique<openvdb::points::AttributeHandle<openvdb::Vec3f>>(
                    leaf->constAttributeArray("v"));
            if (hasDensity)
                density = std::make_unique<openvdb::points::AttributeHandle<float>>(
                    leaf->constAttributeArray("density"));
            if (hasId)
                id = std::make_unique<openvdb::points::AttributeHandle<std::int32_t>>(
                    leaf->constAttributeArray("id"));
            for (auto it = leaf->beginIndexOn(); it; ++it) {
                const openvdb::Vec3d world =
                    transform.indexToWorld(position.get(*it) + it.getCoord().asVec3d());
                frame.position.push_back({float(world.x()), float(world.y()), float(world.z())});
                if (velocity) {
                    const openvdb::Vec3f v = velocity->get(*it);
                    frame.velocity.push_back({v.x(), v.y(), v.z()});
                }
                if (density) frame.density.push_back(density->get(*it));
                if (id) {
                    const std::int32_t value = id->get(*it);
                    if (value < 0) fail(path, "negative particle id " + std::to_string(value));
                    frame.id.push_back(static_cast<std::uint64_t>(value));
                }
            }
        }
    } catch (const openvdb::Exception& e) {
        fail(path, std::string("not a readable OpenVDB point file: ") + e.what());
    }
    const std::size_t n = frame.position.size();
    if ((!frame.velocity.empty() && frame.velocity.size() != n) ||
        (!frame.density.empty() && frame.density.size() != n) ||
        (!frame.id.empty() && frame.id.size() != n))
        fail(path, "point attributes are missing in some leaves");
    if (!frame.id.empty()) {  // back into id order
        std::vector<std::size_t> order(n);
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::sort(order.begin(), order.end(),
                  [&](std::size_t a, std::size_t b) { return frame.id[a] < frame.id[b]; });
        ParticleFrame sorted;
        for (std::size_t k : order) {
            sorted.position.push_back(frame.position[k]);
            if (!frame.velocity.empty()) sorted.velocity.push_back(frame.velocity[k]);
            if (!frame.density.empty()) sorted.density.push_back(frame.density[k]);
            sorted.id.push_back(frame.id[k]);
        }
        frame = std::move(sorted);
    }
    return frame;
}

}  // namespace pbf::surface
