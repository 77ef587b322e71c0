// White water: diffuse particles (spray, foam, air bubbles) after Ihmsen,
// Akinci, Akinci & Teschner 2012, "Unified spray, foam and air bubbles for
// particle-based fluids", The Visual Computer 28(6-8).
//
// A one-way coupled post-process of the fluid's frames (the paper computes
// it after each fluid step and feeds nothing back, section 1): per substep
//  * every fluid particle i gets three potentials (section 4), each mapped to
//    [0, 1] by the clamp Phi(I, tmin, tmax) (eq. 1):
//      trapped air  v_diff = sum_j |v_ij| (1 - v̂_ij . x̂_ij) W(x_ij)   (eq. 2),
//      wave crest   kappa  = sum_j (1 - n̂_i . n̂_j) W(x_ij) over the j behind
//                   i (x̂_ji . n̂_i < 0), kept where v̂_i . n̂_i >= 0.6 (eq. 4-6),
//      kinetic energy  E_k = 1/2 |v_i|^2 per unit mass                (eq. 7),
//    with W(x) = 1 - |x| / h (eq. 3) and n̂ the normalised colour-field
//    gradient;
//  * it emits I_k (k_ta I_ta + k_wc I_wc) dt diffuse particles on average
//    (eq. 8), placed uniformly in the cylinder of radius r around it along
//    its velocity over dt and given its velocity plus the radial offset
//    (eq. 9-10, with the offset as a velocity of 1/s);
//  * every diffuse particle is classified by its number of fluid
//    neighbours within h (section 5): spray (< 6) flies ballistically,
//    bubbles (> 20) rise with buoyancy k_b and drag k_d towards the fluid
//    velocity (eq. 11), foam (between) moves with the fluid's velocity
//    (eq. 12) and dies when its lifetime is used up.
//
// Deterministic: random numbers come from a counter-based generator keyed
// by (seed, frame, substep, fluid particle id, draw), and every particle's
// work writes only its own output, so any thread count gives the same bits.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "pbf/core/vec3.hpp"
#include "pbf/io/io.hpp"

namespace pbf::surface {

enum class DiffuseType : std::uint8_t { spray = 0, foam = 1, bubble = 2 };

struct DiffuseParams {
    float particleRadius = 0.0f;  // r of the fluid, m (> 0, required)
    std::uint64_t seed = 1;
    Vec3 gravity{0.0f, -9.81f, 0.0f};  // m/s^2
    float kernelRadius = 4.0f;         // h in r (the PBF support), [2, 8]
    int substeps = 4;                  // per frame, [1, 100]
    // Clamp ranges of the potentials (eq. 1). Trapped air in m/s, wave
    // crest dimensionless, kinetic energy in J/kg. Chosen above the motion
    // of settled water (speeds below 0.1 m/s) so a resting tank makes none.
    float trappedAirMin = 2.0f, trappedAirMax = 12.0f;
    float waveCrestMin = 1.0f, waveCrestMax = 6.0f;
    float energyMin = 0.5f, energyMax = 5.0f;  // |v| from 1 to 3.2 m/s
    // Emission rates at full potential, diffuse particles per fluid particle
    // per second (the paper's k_ta, k_wc).
    float trappedAirRate = 40.0f, waveCrestRate = 40.0f;
    float lifetimeMin = 1.0f, lifetimeMax = 3.0f;  // s, foam's lifetime
    int sprayMaxNeighbors = 6;                     // fewer fluid neighbours: spray
    int bubbleMinNeighbors = 20;                   // more: bubble
    float buoyancy = 2.0f;                         // k_b, in units of -g
    float drag = 0.5f;                             // k_d, fraction per substep
};

// "" when valid, else "field: problem" (field names as `pbf foam` options).
std::string validate(const DiffuseParams& params);

struct DiffuseParticles {
    std::vector<Vec3> position;  // m
    std::vector<Vec3> velocity;  // m/s
    std::vector<DiffuseType> type;
    std::vector<float> lifetime;    // s left
    std::vector<std::uint64_t> id;  // in order of creation
    std::size_t size() const { return position.size(); }
    std::size_t count(DiffuseType t) const;
};

class DiffuseSimulator {
  public:
    explicit DiffuseSimulator(const DiffuseParams& params);  // throws std::invalid_argument

    // Advances from fluid frame `frame` (`from`) to the next (`to`) over
    // `seconds`, the fluid interpolated linearly in between (particles
    // matched by id; frames sorted by id as pbf run writes them).
    void advance(int frame, const ParticleFrame& from, const ParticleFrame& to, double seconds);
    const DiffuseParticles& particles() const { return particles_; }
    // Seconds spent in the last advance(), per substep.
    double lastSecondsPerSubstep() const { return secondsPerSubstep_; }

  private:
    DiffuseParams params_;
    DiffuseParticles particles_;
    std::uint64_t nextId_ = 0;
    double secondsPerSubstep_ = 0.0;
};

// Binary little-endian PLY like the particle frames: x y z vx vy vz (float),
// type (uchar: 0 spray, 1 foam, 2 bubble), lifetime (float), id (uint; one
// past 32 bits throws, plyId). Atomic. Throws IoError.
void writeDiffusePly(const std::filesystem::path& path, const DiffuseParticles& particles);
// Reads a file written by writeDiffusePly (that exact layout). Throws IoError
// naming the file for anything else, a truncated file or an unknown type.
DiffuseParticles readDiffusePly(const std::filesystem::path& path);
// OpenVDB points (grid "diffuse"): P, v, type (int32), lifetime, id. Atomic.
void writeDiffuseVdb(const std::filesystem::path& path, const DiffuseParticles& particles);

}  // namespace pbf::surface
