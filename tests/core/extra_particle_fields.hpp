// Two fields added to the particle list for pbf_particle_fields_tests
// (included first in each of its sources by tests/CMakeLists.txt):
// a saved 3-vector and an optional integer.
#pragma once

#define PBF_TEST_EXTRA_FIELDS 1
#define PBF_EXTRA_PARTICLE_FIELDS(X)                  \
    X(testVector, float, 3, "m", Saved, "test field") \
    X(testTag, std::uint32_t, 1, "", Optional, "test field")
