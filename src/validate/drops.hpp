// Helpers of the surface-tension cases (private header): worlds made of
// drops of any shape, and what is measured on them.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "pbf/world/world.hpp"

namespace pbf::validation::detail {

// Water (sigma 0.0728 N/m, rho0 1000 kg/m^3) without gravity in a cube of
// side `domainSide` centred on the origin, particles of radius `radius`.
WorldDef waterWorld(float radius, float domainSide, float surfaceTension = 0.0728f);

// The sites of the rest lattice (spacing 2 r, one site at `origin`) for
// which `inside` is true, within `bounds`.
std::vector<Vec3> latticeSites(const WorldDef& def, const Aabb& bounds, const Vec3& origin,
                               const std::function<bool(const Vec3&)>& inside);

// The k-th shift of the lattice, in spacings (each component in [0, 1)):
// the additive recurrence on the powers of g, g^4 = g + 1 (Roberts' R3
// sequence), which covers the cell evenly for any count; k = 0 is no
// shift. A drop cut from the lattice is one sampling of its shape by the
// lattice; the shifts give others (rayleigh_drop, laplace).
Vec3 latticeShift(int k);

// A World holding exactly these particles at rest: a fluid block of one
// lattice site at sites[0] (a world needs one), the rest added.
World worldOf(WorldDef def, const std::vector<Vec3>& sites);

// The particles' positions (memory order) and their centre.
std::vector<Vec3> positions(const World& world);
Vec3 centroid(const std::vector<Vec3>& x);

// Connected components of the particles linked closer than `link` (m).
std::size_t clusterCount(const std::vector<Vec3>& x, float link);
// The sizes of those components, largest first.
std::vector<std::size_t> clusterSizes(const std::vector<Vec3>& x, float link);
// The positions of the largest of those components (the first, on a tie).
std::vector<Vec3> largestCluster(const std::vector<Vec3>& x, float link);
// Each particle's distance to its nearest neighbour (`reach` where none is
// closer than that).
std::vector<double> nearestNeighborDistances(const std::vector<Vec3>& x, float reach);
// The smallest distance between two particles.
double smallestPairDistance(const std::vector<Vec3>& x, float reach);

}  // namespace pbf::validation::detail
