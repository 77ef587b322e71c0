// The statistics the validation cases share (src/validate/measure.hpp).
#include "validate/measure.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace pbf::validation::detail {
namespace {

// Catches a standard deviation over n instead of n - 1 (1.118 here), a
// standard error not divided by sqrt(n), and a spread for one sample
// (the cases' standard errors decide the Rayleigh convergence check).
TEST(SampleStatistics, MeanStandardDeviationAndStandardError) {
    const SampleMean m = sampleMean({1.0, 2.0, 3.0, 4.0});
    EXPECT_DOUBLE_EQ(m.mean, 2.5);
    EXPECT_DOUBLE_EQ(m.standardDeviation, std::sqrt(5.0 / 3.0));
    EXPECT_DOUBLE_EQ(m.standardError(), std::sqrt(5.0 / 3.0) / 2.0);
    EXPECT_EQ(m.count, 4u);
    const SampleMean one = sampleMean({7.0});
    EXPECT_DOUBLE_EQ(one.mean, 7.0);
    EXPECT_EQ(one.standardDeviation, 0.0);
    EXPECT_EQ(one.standardError(), 0.0);
    EXPECT_EQ(sampleMean({}).count, 0u);
}

}  // namespace
}  // namespace pbf::validation::detail
