// The cases of `pbf validate`, in the order they run (include/pbf/validate/validate.hpp).
// A case is one function returning a Case; add it to the list below.
#include "pbf/validate/validate.hpp"

namespace pbf::validation {

Case martinMoyceCase();
Case hydrostaticCase();
Case freeFallCase();
Case momentumCase();
Case taylorGreenCase();
Case archimedesCase();
Case rayleighDropCase();
Case cubeToSphereCase();
Case wettingCase();
Case laplaceCase();
Case heaveCase();
Case openChannelCase();
Case standingWaveCase();
Case waveMakerCase();
Case sloshingCase();
Case pinchOffCase();

const std::vector<Case>& cases() {
    static const std::vector<Case> all{
        martinMoyceCase(),  hydrostaticCase(),  freeFallCase(),  momentumCase(),
        taylorGreenCase(),  archimedesCase(),   heaveCase(),     rayleighDropCase(),
        cubeToSphereCase(), laplaceCase(),      wettingCase(),   pinchOffCase(),
        openChannelCase(),  standingWaveCase(), waveMakerCase(), sloshingCase()};
    return all;
}

}  // namespace pbf::validation
