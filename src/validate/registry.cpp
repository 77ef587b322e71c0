// The cases of `pbf validate`, in the order they run (include/pbf/validate.hpp).
//
// Archimedes floating depths (cubes of 250, 500 and 750 kg/m^3 floating at
// a quarter, half and three quarters of their height) wait for rigid bodies:
// see docs/validation.md, "Archimedes (to do)". A case is one function
// returning a Case; add it to the list below.
#include "pbf/validate.hpp"

namespace pbf::validation {

Case martinMoyceCase();
Case hydrostaticCase();
Case freeFallCase();
Case momentumCase();
Case taylorGreenCase();

const std::vector<Case>& cases() {
    static const std::vector<Case> all{martinMoyceCase(), hydrostaticCase(), freeFallCase(),
                                       momentumCase(), taylorGreenCase()};
    return all;
}

}  // namespace pbf::validation
