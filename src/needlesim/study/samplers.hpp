#pragma once
// Sampling plans on the unit hypercube / index grids, independent of what is sampled.
#include <cstdint>
#include <vector>

namespace needlesim::study {

// Cartesian product of sizes: every combination of indices, last index fastest.
std::vector<std::vector<int>> gridIndices(const std::vector<int>& sizes);

// Latin hypercube: n samples in [0,1)^d, one in each of n equal strata per
// dimension, strata randomly permuted per dimension; deterministic for a seed.
std::vector<std::vector<double>> latinHypercube(int n, int d, std::uint64_t seed);

}  // namespace needlesim::study
