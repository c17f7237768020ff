// Direction sets on the unit sphere, as pure functions of (seed, index): the same set comes out
// on the CPU and the GPU. (Interface fixed here; implementation in progress.)
#pragma once

#include "shprt/core/hd.hpp"
#include "shprt/core/vec.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace shprt {

enum class SamplerKind {
    uniform,     // the paper's set: (θ, φ) = (2·acos(√(1−x)), 2π·y), x, y from the counter RNG
    stratified,  // jittered grid in (cos θ, φ)
    fibonacci,   // spherical Fibonacci lattice
    sobol,       // Sobol (0,2)-sequence mapped to the sphere, Owen-scrambled by seed
};

const char* to_string(SamplerKind kind);
SamplerKind parse_sampler_kind(const std::string& name);  // throws Error(invalid_argument)

// A direction set with integration weights: ∫ f dω ≈ Σ_s weights[s] · f(dirs[s]).
// Monte Carlo sets carry the constant weight 4π/S; quadrature sets carry exact weights.
struct DirectionSet {
    std::vector<float> dirs;     // xyz triples, unit length, S of them
    std::vector<float> weights;  // S weights
    std::size_t size() const { return weights.size(); }
};

}  // namespace shprt
