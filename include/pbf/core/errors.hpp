// Errors of the public API that every part may report.
#pragma once

#include <stdexcept>

namespace pbf {

// An invalid scene or world definition, an invalid live setting or a broken
// mesh: the message names the file (when there is one) and the field, e.g.
// "scenes/x.json: solver.iterations: must be in [1, 100], got 0".
class SceneError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace pbf
