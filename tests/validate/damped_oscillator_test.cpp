// The heave case's fit (src/validate/damped_oscillator.hpp): a damped
// oscillator's parameters from a record, and the natural period's standard
// error, checked against the spread of the fitted periods over many noisy
// records of the same oscillator.
#include "validate/damped_oscillator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace pbf::validation::detail {
namespace {

// The heave case's oscillator: 0.43 s, damping ratio 0.27, 1 cm amplitude.
constexpr double kOmega = 14.0, kSigma = 4.0;
constexpr double kDt = 0.008, kLength = 1.3;

std::vector<double> times() {
    std::vector<double> t;
    for (int k = 0; double(k) * kDt <= kLength; ++k) t.push_back(double(k) * kDt);
    return t;
}

double oscillator(double t) {
    return 0.002 +
           std::exp(-kSigma * t) * (0.01 * std::cos(kOmega * t) + 0.003 * std::sin(kOmega * t));
}

double naturalPeriod() {
    return 2.0 * std::numbers::pi / std::hypot(kOmega, kSigma);
}

// The standard deviation of the fitted natural periods over `records` noisy
// records (noise: AR(1) with lag-1 correlation `rho` and standard deviation
// `noise`), and the mean of the standard errors the fit reported.
struct Spread {
    double measured = 0.0, reported = 0.0;
};
Spread spread(int records, double noise, double rho) {
    const std::vector<double> t = times();
    std::mt19937_64 random(20261125);
    std::normal_distribution<double> normal(0.0, noise * std::sqrt(1.0 - rho * rho));
    double sum = 0.0, sumSquares = 0.0, reported = 0.0;
    for (int r = 0; r < records; ++r) {
        std::vector<double> y;
        double e = normal(random) / std::sqrt(1.0 - rho * rho);  // stationary start
        for (double tk : t) {
            y.push_back(oscillator(tk) + e);
            e = rho * e + normal(random);
        }
        const DampedOscillatorFit f = fitDampedOscillator(t, y);
        sum += f.naturalPeriod;
        sumSquares += f.naturalPeriod * f.naturalPeriod;
        reported += f.naturalPeriodError;
    }
    const double mean = sum / records;
    return {std::sqrt((sumSquares - records * mean * mean) / (records - 1)), reported / records};
}

// Catches a wrong basis, a wrong natural period (the damped one), a wrong
// damping ratio: an exact record gives back its oscillator (on the fit's
// grid: w and sigma are grid points) with no error.
TEST(DampedOscillatorFit, RecoversAnExactOscillator) {
    const std::vector<double> t = times();
    std::vector<double> y;
    for (double tk : t) y.push_back(oscillator(tk));
    const DampedOscillatorFit f = fitDampedOscillator(t, y);
    EXPECT_NEAR(f.omega, kOmega, 1e-9);
    EXPECT_NEAR(f.sigma, kSigma, 1e-9);
    EXPECT_NEAR(f.offset, 0.002, 1e-9);
    EXPECT_NEAR(f.cosine, 0.01, 1e-9);
    EXPECT_NEAR(f.sine, 0.003, 1e-9);
    EXPECT_NEAR(f.naturalPeriod, naturalPeriod(), 1e-9);
    EXPECT_NEAR(f.dampedPeriod, 2.0 * std::numbers::pi / kOmega, 1e-9);
    EXPECT_NEAR(f.dampingRatio, kSigma / std::hypot(kOmega, kSigma), 1e-9);
    EXPECT_LT(f.rms, 1e-9);
    EXPECT_LT(f.naturalPeriodError, 1e-8);
}

// Catches a wrong Jacobian column, covariance or propagation to the period:
// with white noise the reported standard error must match the spread of the
// fitted periods over 40 records (its sampling error is about 11 %; a
// Jacobian column without its factor t, or the residual sum of squares not
// divided by N - 5, is off by far more). Noise 1 mm, the heave records' fit
// RMS is 0.2-0.6 mm.
TEST(DampedOscillatorFit, StandardErrorMatchesTheSpreadWithWhiteNoise) {
    const Spread s = spread(40, 0.001, 0.0);
    EXPECT_GT(s.measured, 3e-4);  // well above the grid's step in the period (3e-4 / sqrt(12))
    EXPECT_GT(s.reported / s.measured, 0.7);
    EXPECT_LT(s.reported / s.measured, 1.4);
}

// Catches the missing correction for correlated residuals (the level's noise
// is correlated from frame to frame): with AR(1) noise of lag-1 correlation
// 0.8 the uncorrected error would be three times too small.
TEST(DampedOscillatorFit, StandardErrorMatchesTheSpreadWithCorrelatedNoise) {
    const Spread s = spread(40, 0.0005, 0.8);
    EXPECT_GT(s.reported / s.measured, 0.6);
    EXPECT_LT(s.reported / s.measured, 1.6);
}

TEST(DampedOscillatorFit, RefusesShortOrMismatchedRecords) {
    EXPECT_THROW(fitDampedOscillator({0, 1, 2}, {0, 1, 2}), std::invalid_argument);
    EXPECT_THROW(fitDampedOscillator({0, 1, 2, 3, 4, 5, 6}, {0, 1}), std::invalid_argument);
}

// The driven heave's fit: F0 + A cos(w t) + B sin(w t) at a known w, over a
// record that is not a whole number of periods (the frames are one substep
// long). Exact data come back exactly, and a swap of the sine and the cosine
// (the stiffness for the damping) or a lost offset would not.
TEST(HarmonicFit, RecoversOffsetCosineAndSine) {
    const double w = 14.39, dt = 0.0041666;
    std::vector<double> t, y;
    for (double s = 0.44; s < 1.75; s += dt) {
        t.push_back(s);
        y.push_back(2.6 - 0.03 * std::cos(w * s) - 0.11 * std::sin(w * s));
    }
    const HarmonicFit f = fitHarmonic(t, y, w);
    EXPECT_NEAR(f.offset, 2.6, 1e-9);
    EXPECT_NEAR(f.cosine, -0.03, 1e-9);
    EXPECT_NEAR(f.sine, -0.11, 1e-9);
    // With the force's frame-to-frame noise (0.1 N, the driven runs' residual)
    // the two amplitudes stay within 0.02 N over three periods.
    std::mt19937_64 random(20261129);
    std::normal_distribution<double> noise(0.0, 0.1);
    for (double& v : y) v += noise(random);
    const HarmonicFit n = fitHarmonic(t, y, w);
    EXPECT_NEAR(n.cosine, -0.03, 0.02);
    EXPECT_NEAR(n.sine, -0.11, 0.02);
    EXPECT_THROW(fitHarmonic({0, 1}, {0, 1}, w), std::invalid_argument);
    EXPECT_THROW(fitHarmonic({0, 1, 2}, {0, 1}, w), std::invalid_argument);
}

}  // namespace
}  // namespace pbf::validation::detail
