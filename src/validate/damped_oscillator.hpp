// A damped oscillator y = e + exp(-sigma t) (A cos(w t) + B sin(w t))
// fitted to a record by least squares, with the standard error of its
// natural period (the heave case, src/validate/heave.cpp).
#pragma once

#include <vector>

namespace pbf::validation::detail {

struct DampedOscillatorFit {
    double omega = 0.0;                             // w, rad/s (the damped angular frequency)
    double sigma = 0.0;                             // decay rate, 1/s
    double offset = 0.0, cosine = 0.0, sine = 0.0;  // e, A, B
    double rms = 0.0;                               // RMS residual, in the record's unit
    double naturalPeriod = 0.0;                     // 2 pi / sqrt(w^2 + sigma^2), s
    double dampedPeriod = 0.0;                      // 2 pi / w, s
    double dampingRatio = 0.0;                      // sigma / sqrt(w^2 + sigma^2)
    // The residuals' lag-1 autocorrelation r1 (clamped to [0, 0.99]) and the
    // natural period's standard error (s): the linearised least-squares
    // covariance s^2 (J^T J)^-1 of (e, A, B, w, sigma), s^2 = RSS / (N - 5),
    // inflated by (1 + r1) / (1 - r1) for correlated residuals (the AR(1)
    // effective sample size N (1 - r1) / (1 + r1), Santer et al. 2000, J.
    // Geophys. Res. 105(D6) 7337), propagated to the period.
    double residualCorrelation = 0.0;
    double naturalPeriodError = 0.0;
};

// (e, A, B) solved for every (w, sigma) on a grid (w 5-40 rad/s by 0.25,
// sigma 0-20 /s by 0.5), the best pair refined (w by 0.01, sigma by 0.02
// within 0.5 and 1 of it). `t` and `y` have the same length, at least 6.
DampedOscillatorFit fitDampedOscillator(const std::vector<double>& t, const std::vector<double>& y);

// y = e + A cos(w t) + B sin(w t) at a given w by least squares (the fit
// above with sigma = 0): the response to a sinusoidal forcing.
struct HarmonicFit {
    double offset = 0.0, cosine = 0.0, sine = 0.0;  // e, A, B
};
HarmonicFit fitHarmonic(const std::vector<double>& t, const std::vector<double>& y, double w);

}  // namespace pbf::validation::detail
