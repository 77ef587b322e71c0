// Anisotropic kernels for particle surfaces, after Yu & Turk 2013,
// "Reconstructing surfaces of particle-based fluids using anisotropic
// kernels", ACM TOG 32(1):5.
//
// Per particle i (section 3 of the paper, lengths in metres):
//  * neighbours j within R with weights w_ij = 1 - (|x_i - x_j| / R)^3 (eq. 11);
//  * the weighted mean x_w (eq. 10) and the smoothed centre
//    x̄_i = (1 - lambda) x_i + lambda x_w (eq. 6: Laplacian smoothing, which
//    takes the particle noise out of flat water);
//  * the weighted covariance C_i of the neighbours about x_w (eq. 9), its
//    eigen-decomposition C = Q diag(s1 >= s2 >= s3) Q^T, the small
//    eigenvalues raised to s1 / k_r (eq. 13: no axis thinner than 1 / k_r of
//    the longest), and the kernel's semi-axes a_k = h k_s s_k; a particle
//    with N_eps or fewer neighbours keeps a sphere of radius k_n h;
//  * the kernel W(x, G) = sigma det(G) P(|G x|) with G = Q diag(1 / a) Q^T
//    (eq. 8) and P the poly6 profile (1 - q^2)^3 (sigma = 315 / (64 pi)).
//
// k_s: the paper tunes it by hand (1400 in its units). Here it is derived so
// that a particle inside the fluid, whose neighbourhood is a full lattice
// ball, gets exactly the isotropic kernel of radius h: k_s = 1 / s_bulk with
// s_bulk the eigenvalue of that neighbourhood's covariance. Flat water then
// gets kernels of radius h along the surface and about 0.4 h across it.
//
// The surface is the iso-surface phi = c of phi(x) = sum_j V W(x - x̄_j, G_j)
// with V = (2 r)^3, the water volume per particle, so phi is about 1 inside
// the water. c is calibrated on a flat lattice layer (anisotropicIsoValue):
// a flat surface lands one radius above its top particle centres, where the
// isotropic method puts it too, so both keep the water's volume.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "pbf/core/vec3.hpp"
#include "pbf/surface/surface.hpp"

namespace pbf::surface {

struct Ellipsoid {
    Vec3 centre;               // smoothed centre x̄, m
    std::array<Vec3, 3> axes;  // semi-axes (direction times length, m), longest first
    std::array<float, 9> g;    // G, row-major, 1/m: |G (x - centre)| = 1 on the boundary
    Vec3 halfExtent;           // half size of the ellipsoid's axis-aligned box, m
    float peak = 0.0f;         // V sigma det(G): phi contribution at the centre
    int neighbors = 0;         // within the neighbourhood radius, self excluded
};

// The kernels of `positions` (params.particleRadius and the anisotropic
// fields are used). Deterministic: the same bits for any thread count.
// Throws std::invalid_argument for invalid params.
std::vector<Ellipsoid> computeEllipsoids(std::span<const Vec3> positions,
                                         const SurfaceParams& params);

// One kernel's contribution V W(x - x̄, G) at x.
float kernelValue(const Ellipsoid& e, Vec3 x);

// The iso-value c (see above) for these parameters, calibrated once per
// parameter set on a flat lattice layer and cached.
float anisotropicIsoValue(const SurfaceParams& params);

}  // namespace pbf::surface
