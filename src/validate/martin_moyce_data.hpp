// Martin & Moyce 1952, "Part IV. An experimental study of the collapse of
// liquid columns on a rigid horizontal plane", Phil. Trans. R. Soc. A 244,
// 312-324 (doi:10.1098/rsta.1952.0006): the column of square section
// a = 2.25 in (0.05715 m), height n^2 a with n^2 = 2 (private header).
//
// The numbers are Tables 2 and 6 of the paper as tabulated in Ocellaris
// (TormodLandet/Ocellaris, scripts/plot_dam_break.py, "Data from Martin and
// Moyce (1952), Table 2 and 6", with n = sqrt(2), a = 0.05715 m). We could
// not read the paper itself (paywalled). Cross-checks: Lethe
// (chaos-polymtl/lethe, examples/multiphysics/dam-break/dam-break-2d.py)
// lists the same surge front within 0.01-0.03 in T up to Z = 3.67, and the
// values step in the quarter and half inches of the experiment's marks
// (Z in steps of 1/9 and 2/9, H in steps of 1/18 for a = 2.25 in).
#pragma once

#include <array>

namespace pbf::validation::martin_moyce {

inline constexpr double kColumnWidth = 0.05715;  // a, m (2.25 in)
inline constexpr double kHeightRatio = 2.0;      // n^2: the column is n^2 a high

// Table 2: the surge front Z = x / a at T = n t sqrt(g / a).
inline constexpr std::array<double, 15> kFrontT = {0.41, 0.84, 1.19, 1.43, 1.63, 1.83, 1.98, 2.20,
                                                   2.32, 2.51, 2.65, 2.83, 2.98, 3.11, 3.33};
inline constexpr std::array<double, 15> kFrontZ = {1.11, 1.22, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56,
                                                   2.78, 3.00, 3.22, 3.44, 3.67, 3.89, 4.11};

// Table 6: the residual height of the column H = eta / (n^2 a) at the back
// wall at tau = t sqrt(g / a).
inline constexpr std::array<double, 17> kHeightTau = {0.56, 0.77, 0.93, 1.08, 1.28, 1.46,
                                                      1.66, 1.84, 2.00, 2.21, 2.45, 2.70,
                                                      3.06, 3.44, 4.20, 5.25, 7.40};
inline constexpr std::array<double, 17> kHeightH = {0.94, 0.89, 0.83, 0.78, 0.72, 0.67,
                                                    0.61, 0.56, 0.50, 0.44, 0.39, 0.33,
                                                    0.28, 0.22, 0.17, 0.11, 0.06};

}  // namespace pbf::validation::martin_moyce
