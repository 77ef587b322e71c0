#include "validate/constraint_pairs.hpp"

#include <array>
#include <cmath>

namespace pbf::validation::detail {

ConstraintPairs fitConstraintPairs(const std::vector<Vec3>& x, const std::vector<Vec3>& a,
                                   const std::vector<std::vector<std::uint32_t>>& neighbours,
                                   const SpikyKernel& kernel, int iterations) {
    // In doubles, the kernel gradients scaled to order one (they are ~1e13 in
    // SI units at millimetre spacings; L carries the scale back at the end).
    using D3 = std::array<double, 3>;
    const std::size_t n = x.size();
    const double scale =
        std::fabs(double(kernel.gradientCoefficient)) * double(kernel.h) * double(kernel.h);
    std::vector<std::vector<D3>> g(n);   // g[i][k] = grad W(x_i - x_{neighbours[i][k]}) / scale
    std::vector<D3> own(n, D3{}), b(n);  // own[i] = sum_k g[i][k]
    for (std::size_t i = 0; i < n; ++i) {
        b[i] = {double(a[i].x), double(a[i].y), double(a[i].z)};
        for (const std::uint32_t j : neighbours[i]) {
            const Vec3 rij = x[i] - x[j];
            const Vec3 gij = kernel.gradient(rij, length(rij));
            g[i].push_back({double(gij.x) / scale, double(gij.y) / scale, double(gij.z) / scale});
            for (int e = 0; e < 3; ++e) own[i][e] += g[i].back()[e];
        }
    }
    const auto dot = [](const D3& u, const D3& v) {
        return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    };
    const auto norm2 = [&](const std::vector<D3>& v) {
        double s = 0.0;
        for (const D3& q : v) s += dot(q, q);
        return s;
    };
    // (A L)_i = L_i own_i + sum_k L_{j_k} g_ik.
    const auto apply = [&](const std::vector<double>& L, std::vector<D3>& out) {
        for (std::size_t i = 0; i < n; ++i) {
            D3 o{L[i] * own[i][0], L[i] * own[i][1], L[i] * own[i][2]};
            for (std::size_t k = 0; k < neighbours[i].size(); ++k)
                for (int e = 0; e < 3; ++e) o[e] += L[neighbours[i][k]] * g[i][k][e];
            out[i] = o;
        }
    };
    // (A^T u)_k = u_k . own_k + sum_{i: k in N(i)} u_i . g_ik, and g_ik = -g_ki
    // (the gradient is odd; the neighbour lists are symmetric).
    const auto applyTransposed = [&](const std::vector<D3>& u, std::vector<double>& out) {
        for (std::size_t k = 0; k < n; ++k) {
            double o = dot(u[k], own[k]);
            for (std::size_t m = 0; m < neighbours[k].size(); ++m)
                o -= dot(u[neighbours[k][m]], g[k][m]);
            out[k] = o;
        }
    };
    ConstraintPairs fit;
    fit.L.assign(n, 0.0);
    const double b2 = norm2(b);
    if (!(b2 > 0.0)) return fit;
    std::vector<double> s(n), p(n);
    std::vector<D3> r = b, q(n);
    applyTransposed(r, s);
    p = s;
    double gamma = 0.0;
    for (const double v : s) gamma += v * v;
    for (int it = 0; it < iterations && gamma > 1e-30 * b2; ++it) {
        apply(p, q);
        const double qq = norm2(q);
        if (!(qq > 0.0)) break;
        const double alpha = gamma / qq;
        for (std::size_t i = 0; i < n; ++i) {
            fit.L[i] += alpha * p[i];
            for (int e = 0; e < 3; ++e) r[i][e] -= alpha * q[i][e];
        }
        applyTransposed(r, s);
        double next = 0.0;
        for (const double v : s) next += v * v;
        const double beta = next / gamma;
        gamma = next;
        for (std::size_t i = 0; i < n; ++i) p[i] = s[i] + beta * p[i];
    }
    fit.residual = std::sqrt(norm2(r) / b2);
    for (double& l : fit.L) l /= scale;
    return fit;
}

}  // namespace pbf::validation::detail
