#include "pbf/particles.hpp"

#include <algorithm>
#include <numeric>
#include <utility>

#include "core/parallel.hpp"

namespace pbf {
namespace {

template <class T>
void permute(std::vector<T>& values, std::span<const std::uint32_t> perm, std::vector<T>& scratch) {
    scratch.resize(values.size());
    detail::parallelFor(values.size(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) scratch[k] = values[perm[k]];
    });
    values.swap(scratch);
}

}  // namespace

void ParticleStore::reserve(std::size_t n) {
    position.reserve(n);
    predicted.reserve(n);
    velocity.reserve(n);
    density.reserve(n);
    id.reserve(n);
}

void ParticleStore::add(const Vec3& x, const Vec3& v, float restDensity) {
    position.push_back(x);
    predicted.push_back(x);
    velocity.push_back(v);
    density.push_back(restDensity);
    id.push_back(nextId_++);
    if (!solveAcceleration.x.empty()) solveAcceleration.push_back({});
}

void ParticleStore::reorder(std::span<const std::uint32_t> perm) {
    for (Float3Array* a : {&position, &predicted, &velocity, &solveAcceleration}) {
        if (a->size() != perm.size()) continue;  // an optional field that is off
        permute(a->x, perm, scratchFloat_);
        permute(a->y, perm, scratchFloat_);
        permute(a->z, perm, scratchFloat_);
    }
    permute(density, perm, scratchFloat_);
    permute(id, perm, scratchIndex_);
}

void ParticleStore::keepRange(std::size_t begin, std::size_t end) {
    auto keep = [&](auto& values) {
        values.erase(values.begin() + static_cast<std::ptrdiff_t>(end), values.end());
        values.erase(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(begin));
    };
    for (Float3Array* a : {&position, &predicted, &velocity, &solveAcceleration}) {
        if (a->x.empty()) continue;  // the solve acceleration while the warm start is off
        keep(a->x);
        keep(a->y);
        keep(a->z);
    }
    keep(density);
    keep(id);
}

std::vector<std::uint32_t> ParticleStore::orderById() const {
    std::vector<std::uint32_t> order(size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return id[a] < id[b]; });
    return order;
}

std::size_t ParticleStore::memoryBytes() const {
    std::size_t floats = density.capacity() + scratchFloat_.capacity();
    for (const Float3Array* a : {&position, &predicted, &velocity, &solveAcceleration})
        floats += a->x.capacity() + a->y.capacity() + a->z.capacity();
    return sizeof(float) * floats +
           sizeof(std::uint32_t) * (id.capacity() + scratchIndex_.capacity());
}

}  // namespace pbf
