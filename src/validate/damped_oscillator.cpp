#include "validate/damped_oscillator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace pbf::validation::detail {
namespace {

// Solves m x = b in place by Gaussian elimination with partial pivoting
// (m is N x N, b its right-hand sides as extra columns). False when singular.
template <std::size_t N, std::size_t C>
bool solve(std::array<std::array<double, N + C>, N>& m) {
    for (std::size_t i = 0; i < N; ++i) {
        std::size_t pivot = i;
        for (std::size_t r = i + 1; r < N; ++r)
            if (std::fabs(m[r][i]) > std::fabs(m[pivot][i])) pivot = r;
        std::swap(m[i], m[pivot]);
        if (!(std::fabs(m[i][i]) > 1e-300)) return false;
        for (std::size_t r = 0; r < N; ++r) {
            if (r == i) continue;
            const double f = m[r][i] / m[i][i];
            for (std::size_t c = i; c < N + C; ++c) m[r][c] -= f * m[i][c];
        }
    }
    for (std::size_t i = 0; i < N; ++i)
        for (std::size_t c = N; c < N + C; ++c) m[i][c] /= m[i][i];
    return true;
}

struct Linear {
    std::array<double, 3> coefficients{};                       // e, A, B
    double residual = std::numeric_limits<double>::infinity();  // sum of squares
};

// The best (e, A, B) for one (w, sigma): the normal equations of the linear
// least squares.
Linear linearFit(const std::vector<double>& t, const std::vector<double>& y, double w,
                 double sigma) {
    const auto basis = [&](std::size_t k) {
        const double decay = std::exp(-sigma * t[k]);
        return std::array<double, 3>{1.0, decay * std::cos(w * t[k]), decay * std::sin(w * t[k])};
    };
    std::array<std::array<double, 4>, 3> m{};
    for (std::size_t k = 0; k < t.size(); ++k) {
        const std::array<double, 3> c = basis(k);
        for (std::size_t i = 0; i < 3; ++i) {
            for (std::size_t j = 0; j < 3; ++j) m[i][j] += c[i] * c[j];
            m[i][3] += c[i] * y[k];
        }
    }
    Linear fit;
    if (!solve<3, 1>(m)) return fit;
    fit.coefficients = {m[0][3], m[1][3], m[2][3]};
    fit.residual = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
        const std::array<double, 3> c = basis(k);
        const std::array<double, 3>& x = fit.coefficients;
        const double d = x[0] * c[0] + x[1] * c[1] + x[2] * c[2] - y[k];
        fit.residual += d * d;
    }
    return fit;
}

// The natural period's standard error (see DampedOscillatorFit).
void addPeriodError(const std::vector<double>& t, const std::vector<double>& y,
                    DampedOscillatorFit& f) {
    constexpr std::size_t kParameters = 5;  // e, A, B, w, sigma
    const std::size_t n = t.size();
    std::array<std::array<double, 2 * kParameters>, kParameters> m{};
    std::vector<double> residual(n);
    double sum = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        const double decay = std::exp(-f.sigma * t[k]);
        const double c = std::cos(f.omega * t[k]), s = std::sin(f.omega * t[k]);
        const double oscillation = f.cosine * c + f.sine * s;
        // d y / d(e, A, B, w, sigma)
        const std::array<double, kParameters> j{1.0, decay * c, decay * s,
                                                decay * t[k] * (f.sine * c - f.cosine * s),
                                                -t[k] * decay * oscillation};
        for (std::size_t a = 0; a < kParameters; ++a)
            for (std::size_t b = 0; b < kParameters; ++b) m[a][b] += j[a] * j[b];
        residual[k] = f.offset + decay * oscillation - y[k];
        sum += residual[k] * residual[k];
    }
    for (std::size_t a = 0; a < kParameters; ++a) m[a][kParameters + a] = 1.0;
    double lag = 0.0;
    for (std::size_t k = 1; k < n; ++k) lag += residual[k] * residual[k - 1];
    f.residualCorrelation = sum > 0.0 ? std::clamp(lag / sum, 0.0, 0.99) : 0.0;
    if (!solve<kParameters, kParameters>(m)) {
        f.naturalPeriodError = std::numeric_limits<double>::infinity();
        return;
    }
    const double variance = sum / double(n - kParameters) * (1.0 + f.residualCorrelation) /
                            (1.0 - f.residualCorrelation);
    // T = 2 pi / sqrt(w^2 + sigma^2): dT/dw = -T w / (w^2 + sigma^2), likewise sigma.
    const double natural2 = f.omega * f.omega + f.sigma * f.sigma;
    const std::array<double, 2> g{-f.naturalPeriod * f.omega / natural2,
                                  -f.naturalPeriod * f.sigma / natural2};
    double periodVariance = 0.0;
    for (std::size_t a = 0; a < 2; ++a)
        for (std::size_t b = 0; b < 2; ++b)
            periodVariance += g[a] * m[3 + a][kParameters + 3 + b] * g[b];
    f.naturalPeriodError = std::sqrt(std::max(0.0, variance * periodVariance));
}

}  // namespace

DampedOscillatorFit fitDampedOscillator(const std::vector<double>& t,
                                        const std::vector<double>& y) {
    if (t.size() != y.size() || t.size() < 6)
        throw std::invalid_argument(
            "fitDampedOscillator: needs at least 6 samples, as many t as y");
    double bestResidual = std::numeric_limits<double>::infinity();
    double bestW = 0.0, bestSigma = 0.0;
    const auto search = [&](double w0, double w1, double dw, double s0, double s1, double ds) {
        for (double w = w0; w <= w1 + 1e-12; w += dw)
            for (double sigma = std::max(0.0, s0); sigma <= s1 + 1e-12; sigma += ds) {
                const double residual = linearFit(t, y, w, sigma).residual;
                if (residual < bestResidual) {
                    bestResidual = residual;
                    bestW = w;
                    bestSigma = sigma;
                }
            }
    };
    // Periods 0.16-1.3 s, damping rates 0-20 /s; then refined around the best.
    search(5.0, 40.0, 0.25, 0.0, 20.0, 0.5);
    const double w = bestW, sigma = bestSigma;
    search(w - 0.5, w + 0.5, 0.01, sigma - 1.0, sigma + 1.0, 0.02);
    DampedOscillatorFit f;
    f.omega = bestW;
    f.sigma = bestSigma;
    const Linear best = linearFit(t, y, bestW, bestSigma);
    f.offset = best.coefficients[0];
    f.cosine = best.coefficients[1];
    f.sine = best.coefficients[2];
    const double natural = std::hypot(bestW, bestSigma);
    f.naturalPeriod = 2.0 * std::numbers::pi / natural;
    f.dampedPeriod = 2.0 * std::numbers::pi / bestW;
    f.dampingRatio = bestSigma / natural;
    f.rms = std::sqrt(bestResidual / double(t.size()));
    addPeriodError(t, y, f);
    return f;
}

HarmonicFit fitHarmonic(const std::vector<double>& t, const std::vector<double>& y, double w) {
    if (t.size() != y.size() || t.size() < 3)
        throw std::invalid_argument(
            "fitHarmonic: needs at least 3 samples, as many times as values");
    const std::array<double, 3> c = linearFit(t, y, w, 0.0).coefficients;
    return {c[0], c[1], c[2]};
}

}  // namespace pbf::validation::detail
