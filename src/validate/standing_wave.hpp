// The standing-wave measurement of the `standing_wave` case (private header;
// also used by tests/validate/standing_wave_test.cpp): a closed tank's first
// mode started from linear theory's velocity field, its velocity amplitude
// recorded and fitted with a damped oscillator.
#pragma once

#include <cstddef>
#include <vector>

#include "validate/damped_oscillator.hpp"

namespace pbf::validation::detail {

struct StandingWave {
    float radius = 0.0f;
    float consistentCorrection = 0.0f;  // solver.consistent_correction
    std::size_t particles = 0;
    std::vector<double> t, amplitude;  // the mode's amplitude / its start
    DampedOscillatorFit fit;
    double omega = 0.0;  // natural angular frequency, rad/s
};

// Linear theory's w = sqrt(g k tanh(k h)) of the tank, rad/s.
double standingWaveTheoryOmega();

// The tank at this particle radius, left to oscillate for `duration` s.
StandingWave standingWave(float radius, float consistentCorrection = 0.0f, double duration = 4.0);

}  // namespace pbf::validation::detail
