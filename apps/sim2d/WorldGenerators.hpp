// Worlds made on the command line: `--generate KIND:N` (with `--seed S`), all in a 256 x 256 grid of
// 1-unit voxels, deterministic for a given seed (std::mt19937_64, whose output the standard fixes, mapped
// to doubles by hand: the standard's distributions may differ between libraries).
//
//   city:N   N moving circles and boxes in the streets and through the blocks of a city: 8 x 8 blocks of
//            24 x 24 units between 8-unit streets, each block filled with 1 to 4 static buildings.
//   maze:N   N movers in an indoor maze: 16-unit rooms, 2-unit static walls with one doorway per wall
//            on the spanning tree of the rooms and a few more.
//   field:N  N movers in a sparse open field with 40 static rocks (circles and convex polygons).
//
// Movers have speeds in [0.15, 0.9] units per frame (maxSpeed = speed), sizes from 0.6 to 2.5 units.
#pragma once

#include "SimWorld.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace rgvc::sim {

struct GeneratorSpec {
    std::string kind;       ///< "city", "maze" or "field"
    std::size_t movers = 0; ///< [Limit] 0..100000
};

/// The generator names, for usage texts.
const std::vector<std::string>& generatorKinds();

/// Parses "KIND:N". @throws InvalidInput("--generate", ...) naming what is wrong.
GeneratorSpec parseGeneratorSpec(const std::string& text);

/// The world of `spec` for `seed`; ids: the static objects first from 0, then the movers.
SimWorld generateWorld(const GeneratorSpec& spec, std::uint64_t seed);

} // namespace rgvc::sim
