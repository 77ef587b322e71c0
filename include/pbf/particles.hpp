// Structure-of-arrays particle storage.
//
// Every per-particle attribute is its own contiguous array; a 3-vector
// attribute is three float arrays (x, y, z) so that passes over one component
// stream through memory. `ParticleStore::reorder` is the one place that
// permutes particles: the solver sorts them by grid cell every step so that
// neighbours sit next to each other in memory, and `id` keeps each
// particle's stable identity for output files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "pbf/vec3.hpp"

namespace pbf {

// Three float arrays holding one 3-vector attribute.
struct Float3Array {
    std::vector<float> x;
    std::vector<float> y;
    std::vector<float> z;

    std::size_t size() const { return x.size(); }
    void resize(std::size_t n) {
        x.resize(n);
        y.resize(n);
        z.resize(n);
    }
    void reserve(std::size_t n) {
        x.reserve(n);
        y.reserve(n);
        z.reserve(n);
    }
    Vec3 get(std::size_t i) const { return {x[i], y[i], z[i]}; }
    void set(std::size_t i, const Vec3& v) {
        x[i] = v.x;
        y[i] = v.y;
        z[i] = v.z;
    }
    void push_back(const Vec3& v) {
        x.push_back(v.x);
        y.push_back(v.y);
        z.push_back(v.z);
    }
};

class ParticleStore {
  public:
    // Persistent state, permuted together by reorder().
    Float3Array position;           // x, metres
    Float3Array predicted;          // x*, metres (solver working positions)
    Float3Array velocity;           // v, metres per second
    std::vector<float> density;     // last density estimate, kg/m^3
    // The last substep's pressure acceleration (its position correction per
    // dt^2, m/s^2), which warm-starts the next one (solver.warm_start).
    // Empty while the warm start is off; particles added get zero.
    Float3Array solveAcceleration;
    std::vector<std::uint32_t> id;  // stable identity, 0-based

    std::size_t size() const { return id.size(); }
    void reserve(std::size_t n);
    // Appends a particle with the next free id; density starts at `restDensity`.
    void add(const Vec3& x, const Vec3& v, float restDensity);
    // Permutes every array: new index k takes the particle at old index perm[k].
    // `perm` must be a permutation of [0, size()).
    void reorder(std::span<const std::uint32_t> perm);
    // Keeps the particles [begin, end) (in order) and drops the others.
    void keepRange(std::size_t begin, std::size_t end);
    // Bytes held by the particle arrays and the reorder scratch.
    std::size_t memoryBytes() const;
    // Indices of the particles sorted by id (for writing files in a stable order).
    std::vector<std::uint32_t> orderById() const;
    // The id the next add() gives (saved and restored by checkpoints).
    std::uint32_t nextId() const { return nextId_; }
    void setNextId(std::uint32_t next) { nextId_ = next; }

  private:
    std::uint32_t nextId_ = 0;
    std::vector<float> scratchFloat_;
    std::vector<std::uint32_t> scratchIndex_;
};

}  // namespace pbf
