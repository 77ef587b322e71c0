// Running error bounds for float computations (Wilkinson's running error
// analysis), used to derive the tolerances of the SIMD-vs-reference tests.
//
// A Bound {v, e} stands for a float computation whose exact value, in real
// arithmetic on the float inputs both implementations share, is v, and whose
// computed value lies within e of v. v is evaluated in double; its own
// rounding error (relative 2^-53 per operation) is below 2^-28 of every
// float bound used here and is absorbed by kDoubleSlack.
//
// The arithmetic follows the standard model fl(a op b) = (a op b)(1 + delta),
// |delta| <= u = 2^-24 (round to nearest, no underflow: all quantities here
// are far from the float subnormal range).
//   * The exact operations (add, sub, mul, div, sqrt) propagate the input
//     errors to first and second order; they add no rounding of their own.
//   * rounded(x, k): k roundings that each multiply the result by (1 + delta)
//     (products, quotients, one addition of two values). (1 + u)^k - 1 <=
//     gamma_k = k u / (1 - k u) (Higham, "Accuracy and Stability of
//     Numerical Algorithms", 2nd ed., lemma 3.1), and relative factors
//     commute with the products around them, so k counts the roundings of a
//     product in any order and of constant factors applied before or after
//     a sum (moving a factor (1 + delta) from a sum into its terms is exact).
//   * sum(terms): a float sum of n terms in any order (sequential, by SIMD
//     lanes, tree) differs from the exact sum of the computed terms by at most
//     gamma_{n-1} sum |term| (Higham eq. 4.4 holds for every order); with the
//     terms' own errors e_k the total error is
//     sum e_k + gamma_{n-1} sum (|v_k| + e_k).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace pbf::test {

inline constexpr double kUnitRoundoff = 0x1p-24;
inline constexpr double kDoubleSlack = 0x1p-40;  // relative, see above

inline double gamma(int k) {
    const double ku = k * kUnitRoundoff;
    return ku / (1.0 - ku);
}

struct Bound {
    double v = 0.0;  // exact value
    double e = 0.0;  // |computed - exact| <= e
};

inline Bound exact(double v) {
    return {v, 0.0};
}
inline Bound add(Bound a, Bound b) {
    return {a.v + b.v, a.e + b.e};
}
inline Bound sub(Bound a, Bound b) {
    return {a.v - b.v, a.e + b.e};
}
inline Bound mul(Bound a, Bound b) {
    return {a.v * b.v, std::fabs(a.v) * b.e + std::fabs(b.v) * a.e + a.e * b.e};
}
// Times an exact constant.
inline Bound scale(Bound a, double s) {
    return {a.v * s, std::fabs(s) * a.e};
}
// Needs |b.v| > b.e (the divisor's sign is known).
inline Bound div(Bound a, Bound b) {
    const double margin = std::fabs(b.v) - b.e;
    if (!(margin > 0.0)) return {a.v / b.v, INFINITY};
    return {a.v / b.v, (std::fabs(a.v) * b.e + std::fabs(b.v) * a.e) / (std::fabs(b.v) * margin)};
}
// sqrt is concave: the largest change is on the lower side.
inline Bound sqrtOf(Bound a) {
    const double root = std::sqrt(std::max(a.v, 0.0));
    return {root, root - std::sqrt(std::max(a.v - a.e, 0.0))};
}
// A relative error of at most `relative` on top of the propagated one.
inline Bound relative(Bound a, double relative) {
    return {a.v, a.e + relative * (std::fabs(a.v) + a.e)};
}
// k roundings of the operations that produced `a`.
inline Bound rounded(Bound a, int k) {
    return relative(a, gamma(k) + kDoubleSlack);
}
// max(a, 0) is 1-Lipschitz.
inline Bound positivePart(Bound a) {
    return {std::max(a.v, 0.0), a.e};
}

// A float sum of the terms in any order, plus `extraTerms` terms the caller
// folded into one of them (they count towards n).
inline Bound sum(const std::vector<Bound>& terms, int extraTerms = 0) {
    Bound s;
    double magnitude = 0.0;
    for (const Bound& t : terms) {
        s.v += t.v;
        s.e += t.e;
        magnitude += std::fabs(t.v) + t.e;
    }
    const int n = static_cast<int>(terms.size()) + extraTerms;
    if (n > 1) s.e += (gamma(n - 1) + kDoubleSlack) * magnitude;
    return s;
}

struct Bound3 {
    Bound x, y, z;
    Bound& operator[](int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }
    const Bound& operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
};

}  // namespace pbf::test
