// fastAtan2: atan2 within a stated bound, for the 2D occlusion image's angular bin coordinates.
//
// Why hand-written and not std::atan2: glibc's atan2 is correctly rounded, which costs ~150 instructions
// a call on x86-64 (a library call, argument reduction, a fallback path for hard cases), and the 2D
// image computes one or two per occludee test and per draw: 11-13 % of the instructions of
// rgvc_bench_classes' random and city 2D scenes. The image does not need correct rounding: its angular
// extents are already padded on both sides (OcclusionBuffer2D.hpp, "Rounding"), and a pad that covers
// this function's error keeps every extent a superset of the true one. SLEEF (Debian's libsleef-dev) has
// bounded-error atan2s (Sleef_atan2d1_u35: 3.5 ulp), but as out-of-line calls into a library the
// rendering-free core would then depend on for one function of a dozen lines, which must inline into the
// image's loops to pay; the bound of this one is derived below and checked by the tests.
//
// How. With a = |x|, b = |y|, t = min(a, b) / max(a, b) in [0, 1], atan2 is atan(t) mapped to its octant
// (pi/2 - . when b > a, pi - . when x < 0, the sign of y). atan(t) = t g(t^2) with g(u) = atan(sqrt u) /
// sqrt u, analytic on a disc of radius 1 around 0 (its nearest singularity is at u = -1). g is replaced by
// its degree-9 polynomial p interpolating it at the 10 Chebyshev nodes of [0, 1] (monomial coefficients
// computed at 50 digits with mpmath, rounded to double; Chebyshev interpolants of a function analytic
// inside the Bernstein ellipse through -1, rho = 3 + sqrt 8 for [0, 1], converge like rho^-n).
// The bound. e(t) = t p(t^2) - atan t, evaluated in double (as below, by Estrin's scheme; Horner's rule
// gives the same figure, the two evaluations differing by at most 3.3e-16), was sampled at t = i 1e-8,
// i = 0..10^8, against atanl: its largest magnitude is 1.51e-9. Between samples e moves by at most
// |e'| 0.5e-8, and |e'(t)| = |p(u) + 2 u p'(u) - 1 / (1 + t^2)| <= sum (2k + 1) |c_k| + 1 = 8.31 on [0, 1],
// so |e| <= 1.51e-9 + 4.2e-8 < 1e-7 everywhere in [0, 1]. The octant mapping adds rounding of ~1e-15.
// test_occlusion_buffer2d samples again (every 1e-7 of t, and 10^6 directions around the circle) against std::atan2.
// Special values, as std::atan2 for the signs of zero (the result of +-0 and of a zero x keeps y's
// sign); a NaN in either argument, and both arguments infinite, give NaN (std::atan2 gives +-pi/4 for
// the latter): every caller treats NaN as "direction unknown", which is conservative.
#pragma once

#include <cmath>

namespace rgvc {

/// [Radians] Upper bound on |fastAtan2(y, x) - std::atan2(y, x)| for finite (y, x), not both infinite.
inline constexpr double kFastAtan2MaxError = 1e-7;

/// atan2(y, x) in [-pi, pi] within kFastAtan2MaxError; NaN when either argument is NaN or both are
/// infinite. Branch-free but for the selects (vectorizes when inlined into a loop).
inline double fastAtan2(double y, double x) {
    constexpr double kPi = 3.14159265358979323846, kHalfPi = 0.5 * kPi;
    const double a = std::abs(x), b = std::abs(y);
    const bool steep = b > a; // false for NaN: the quotient below then carries the NaN
    const double num = steep ? a : b, den = steep ? b : a;
    // den == 0: both zero (num <= den), t = 0. inf / inf and NaN give NaN.
    const double t = den == 0 ? 0.0 : num / den;
    // p(u) by Estrin's scheme: pairs, then pairs of pairs, a chain of five products and sums where
    // Horner's rule chained ten of each (perf put most of this function's samples in the 2D walk on that
    // chain; this project builds without FMA, so each step is a product and a sum).
    const double u = t * t, u2 = u * u, u4 = u2 * u2, u8 = u4 * u4;
    const double p01 = 0.9999999971605454 - 0.3333327629198255 * u, p23 = 0.19998075281148714 - 0.14260016082820906 * u;
    const double p45 = 0.10932341501303093 - 0.08349724968301601 * u, p67 = 0.05708955593030619 - 0.030351864785781172 * u;
    const double p89 = 0.010487649254949306 - 0.0017011700640685973 * u;
    const double g = (p01 + p23 * u2) + (p45 + p67 * u2) * u4 + p89 * u8;
    double r = t * g;
    r = steep ? kHalfPi - r : r;
    r = std::signbit(x) ? kPi - r : r;
    return std::signbit(y) ? -r : r;
}

} // namespace rgvc
