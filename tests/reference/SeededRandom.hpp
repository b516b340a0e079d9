// Portable seeded draws for the random scene generators (header-only).
//
// Everything is drawn from std::mt19937_64 through these integer-to-double mappings rather than the
// standard distributions, whose output differs between standard libraries: a seed names the same scene
// on every machine.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace rgvc::reference::seeded {

/// Uniform in [0, 1), 53 random bits.
inline double uniform01(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }
inline double uniform(std::mt19937_64& rng, double a, double b) { return a + (b - a) * uniform01(rng); }
/// Uniform integer in [a, b] (the modulo bias is irrelevant at these ranges).
inline int uniformInt(std::mt19937_64& rng, int a, int b) { return a + int(rng() % std::uint64_t(b - a + 1)); }
inline bool chance(std::mt19937_64& rng, double p) { return uniform01(rng) < p; }
/// Log-uniform in [a, b]: sizes spread evenly over orders of magnitude.
inline double logUniform(std::mt19937_64& rng, double a, double b) {
    return std::exp(uniform(rng, std::log(a), std::log(b)));
}
template <class T> const T& pick(std::mt19937_64& rng, const std::vector<T>& v) { return v[rng() % v.size()]; }

} // namespace rgvc::reference::seeded
