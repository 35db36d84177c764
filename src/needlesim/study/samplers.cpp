#include "needlesim/study/samplers.hpp"

#include <algorithm>
#include <numeric>
#include <random>

namespace needlesim::study {

std::vector<std::vector<int>> gridIndices(const std::vector<int>& sizes) {
  std::vector<std::vector<int>> out;
  if (sizes.empty()) return out;
  for (int s : sizes)
    if (s <= 0) return out;
  std::vector<int> idx(sizes.size(), 0);
  while (true) {
    out.push_back(idx);
    int k = static_cast<int>(sizes.size()) - 1;
    while (k >= 0 && ++idx[k] == sizes[k]) idx[k--] = 0;
    if (k < 0) break;
  }
  return out;
}

std::vector<std::vector<double>> latinHypercube(int n, int d, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::vector<double>> out(n, std::vector<double>(d));
  std::vector<int> perm(n);
  for (int j = 0; j < d; ++j) {
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), rng);
    for (int i = 0; i < n; ++i) out[i][j] = (perm[i] + u(rng)) / n;
  }
  return out;
}

}  // namespace needlesim::study
