// The block colouring of the MPM particle passes (block_colouring.hpp): the
// counting sort of the points by block on all threads, the threads' shares
// of a colour, and its checkpoint.
#include "needlesim/engines/mpm/block_colouring.hpp"

#include <algorithm>
#include <cmath>

#include "needlesim/engines/mpm/pass_support.hpp"

namespace needlesim::mpm {

using pass::teamSize;
using pass::threadId;

void BlockColouring::reset(std::size_t np, const int* nodes, int threads) {
  threads_ = threads;
  std::copy(nodes, nodes + 3, nodes_);
  order_.resize(np);
  for (std::size_t p = 0; p < np; ++p) order_[p] = static_cast<std::uint32_t>(p);
  planned_ = false;
  sorts_ = 0;
}

// Cut at the block boundaries nearest to equal point counts. One thread (no
// blocks): every point in creation order in pass 0.
std::pair<std::size_t, std::size_t> BlockColouring::colourShare(int t, int T, int colour) const {
  if (threads_ == 1) return t == 0 && colour == 0 ? std::pair<std::size_t, std::size_t>{0, order_.size()}
                                                  : std::pair<std::size_t, std::size_t>{0, 0};
  const auto b0 = static_cast<std::ptrdiff_t>(colourStart_[static_cast<std::size_t>(colour)]),
             b1 = static_cast<std::ptrdiff_t>(colourStart_[static_cast<std::size_t>(colour) + 1]);
  const std::size_t p0 = blockStart_[static_cast<std::size_t>(b0)], p1 = blockStart_[static_cast<std::size_t>(b1)];
  const auto cut = [&](int u) -> std::size_t {
    if (u <= 0) return p0;
    if (u >= T) return p1;
    const std::size_t target = p0 + (p1 - p0) * static_cast<std::size_t>(u) / static_cast<std::size_t>(T);
    const auto first = blockStart_.begin() + b0, last = blockStart_.begin() + b1 + 1;
    const auto it = std::lower_bound(first, last, target);  // first boundary >= target (it != first: target >= p0)
    const std::size_t above = *it, below = *(it == first ? it : it - 1);
    return target - below <= above - target ? below : above;
  };
  return {cut(t), cut(t + 1)};
}

std::size_t BlockColouring::blockOf(std::size_t q) const {
  return static_cast<std::size_t>(std::upper_bound(blockStart_.begin(), blockStart_.end(), q) - blockStart_.begin()) - 1;
}

// A point with base node l reaches nodes l .. l + S - 1, so along an axis
// block n reaches nodes kBlock n - 1 .. kBlock n + kBlock + S - 1 and block
// n + 2 starts at kBlock n + 2 kBlock - 1: disjoint for kBlock >= S + 1 (S <=
// 3). Two blocks of one colour are two or more blocks apart along some axis.
void BlockColouring::blockBounds(std::size_t listed, int* lo, int* hi) const {
  std::uint32_t id = blockId_[listed];
  for (int a = 2; a >= 0; --a) {
    const int n = static_cast<int>(id % static_cast<std::uint32_t>(blocks_[a]));
    id /= static_cast<std::uint32_t>(blocks_[a]);
    lo[a] = blockOrigin_[a] + kBlock * n - 1;
    hi[a] = blockOrigin_[a] + kBlock * n + kBlock;
  }
}

// Stable counting sort of the points by colour, then block (base node of the
// support, clamped to the grid), creation order within a block; the blocks
// with points are listed. The passes over the points run on all threads
// (sortPointsByKey), the ranking of the blocks on one.
void BlockColouring::sortByBlock(const PointPositions& pts) {
  const std::size_t np = pts.np;
  const double invh = 1.0 / pts.h;
  const int* nn = nodes_;
  const auto baseNode = [&](std::size_t p, int a) {
    return std::clamp(static_cast<int>(std::floor((pts.x[pts.stride * p + static_cast<std::size_t>(a)] - pts.origin[a]) *
                                                      invh - pts.shift)),
                      0, nn[a] - 1);
  };
  int lo0 = nn[0] - 1, lo1 = nn[1] - 1, lo2 = nn[2] - 1;
#pragma omp parallel for schedule(static) num_threads(threads_) reduction(min : lo0, lo1, lo2)
  for (std::size_t p = 0; p < np; ++p) {
    lo0 = std::min(lo0, baseNode(p, 0));
    lo1 = std::min(lo1, baseNode(p, 1));
    lo2 = std::min(lo2, baseNode(p, 2));
  }
  const int lowest[3] = {lo0, lo1, lo2};
  for (int a = 0; a < 3; ++a) {
    blockOrigin_[a] = lowest[a];
    blocks_[a] = (nn[a] - lowest[a] + kBlock - 1) / kBlock;
  }
  const auto nb1 = static_cast<std::size_t>(blocks_[1]), nb2 = static_cast<std::size_t>(blocks_[2]);
  const std::size_t nblocks = static_cast<std::size_t>(blocks_[0]) * nb1 * nb2;
  // rank of each grid block in colour-major order
  std::vector<std::uint32_t> rank(nblocks), idOfRank(nblocks);
  std::array<std::uint32_t, 9> firstOfColour{};
  std::uint32_t r = 0;
  for (std::size_t c = 0; c < 8; ++c) {
    firstOfColour[c] = r;
    for (std::size_t b = 0; b < nblocks; ++b) {
      const std::size_t bi = b / (nb1 * nb2), bj = b / nb2 % nb1, bk = b % nb2;
      if (((bi & 1) | (bj & 1) << 1 | (bk & 1) << 2) != c) continue;
      idOfRank[r] = static_cast<std::uint32_t>(b);
      rank[b] = r++;
    }
  }
  firstOfColour[8] = r;
  std::vector<std::uint32_t> key(np);
#pragma omp parallel for schedule(static) num_threads(threads_)
  for (std::size_t p = 0; p < np; ++p) {
    std::size_t b = 0;
    for (int a = 0; a < 3; ++a)
      b = b * static_cast<std::size_t>(blocks_[a]) + static_cast<std::size_t>((baseNode(p, a) - blockOrigin_[a]) / kBlock);
    key[p] = rank[b];
  }
  const std::vector<std::uint32_t> start = sortPointsByKey(key, nblocks);  // first entry of each block rank
  blockStart_.clear();
  blockId_.clear();
  for (std::size_t c = 0; c < 8; ++c) {
    colourStart_[c] = static_cast<std::uint32_t>(blockId_.size());
    for (std::uint32_t k = firstOfColour[c]; k < firstOfColour[c + 1]; ++k)
      if (start[k + 1] > start[k]) {
        blockId_.push_back(idOfRank[k]);
        blockStart_.push_back(start[k]);
      }
  }
  colourStart_[8] = static_cast<std::uint32_t>(blockId_.size());
  blockStart_.push_back(static_cast<std::uint32_t>(np));
  planned_ = true;
  ++sorts_;
}

// Stable counting sort of the points by key (< nkeys) into order_ on all
// threads: each thread counts its static share of the points, the offsets run
// key-major, then thread, so order_ is that of the serial stable sort. Returns
// the first entry of each key (nkeys + 1 entries).
std::vector<std::uint32_t> BlockColouring::sortPointsByKey(const std::vector<std::uint32_t>& key, std::size_t nkeys) {
  const std::size_t np = key.size();
  std::vector<std::uint32_t> count(static_cast<std::size_t>(threads_) * nkeys, 0);  // [thread][key]
  std::vector<std::uint32_t> start(nkeys + 1, 0);
  order_.resize(np);
#pragma omp parallel num_threads(threads_)
  {
    const auto t = static_cast<std::size_t>(threadId()), T = static_cast<std::size_t>(teamSize());
    const std::size_t p0 = np * t / T, p1 = np * (t + 1) / T;
    std::uint32_t* c = count.data() + t * nkeys;
    for (std::size_t p = p0; p < p1; ++p) ++c[key[p]];
#pragma omp barrier
#pragma omp single
    {
      std::uint32_t sum = 0;
      for (std::size_t k = 0; k < nkeys; ++k) {
        start[k] = sum;
        for (std::size_t u = 0; u < T; ++u) {
          const std::uint32_t n = count[u * nkeys + k];
          count[u * nkeys + k] = sum;  // thread u's next entry of key k
          sum += n;
        }
      }
      start[nkeys] = sum;
    }
    for (std::size_t p = p0; p < p1; ++p) order_[c[key[p]]++] = static_cast<std::uint32_t>(p);
  }
  return start;
}

ScatterPlan BlockColouring::stats(int team, std::size_t np) const {
  ScatterPlan plan;
  plan.sorts = sorts_;
  if (threads_ == 1 || team <= 1 || np == 0 || !planned_) return plan;
  plan.colours = 0;
  plan.blocks = blockId_.size();
  std::vector<bool> busy(static_cast<std::size_t>(team), false);
  double critical = 0.0;
  for (int c = 0; c < 8; ++c) {
    if (colourStart_[static_cast<std::size_t>(c)] == colourStart_[static_cast<std::size_t>(c) + 1]) continue;
    ++plan.colours;
    std::size_t largest = 0;
    for (int t = 0; t < team; ++t) {
      const auto [q0, q1] = colourShare(t, team, c);
      largest = std::max(largest, q1 - q0);
      if (q1 > q0) busy[static_cast<std::size_t>(t)] = true;
    }
    critical += static_cast<double>(largest);
  }
  plan.busyThreads = static_cast<int>(std::count(busy.begin(), busy.end(), true));
  plan.imbalance = critical * team / static_cast<double>(np);
  return plan;
}

// ---------------------------------------------------------------- checkpoints

// The scatter order (the summation order of p2g) and when to plan it again.
void BlockColouring::save(io::BinaryWriter& w) const {
  w.vec(order_);
  w.vec(blockStart_);
  w.vec(blockId_);
  w.vec(std::vector<std::uint32_t>(colourStart_.begin(), colourStart_.end()));
  for (const int n : blockOrigin_) w.pod(static_cast<std::int32_t>(n));
  for (const int n : blocks_) w.pod(static_cast<std::int32_t>(n));
  w.pod(static_cast<std::uint8_t>(planned_));
}

BlockColouring BlockColouring::read(io::BinaryReader& r, std::size_t np) const {
  BlockColouring b = *this;
  b.order_ = r.vec<std::uint32_t>(np, "scatter order entries");
  for (const std::uint32_t p : b.order_)
    if (p >= np) r.fail("holds a scatter order with a point index out of range (damaged file)");
  b.blockStart_ = r.vec<std::uint32_t>();
  b.blockId_ = r.vec<std::uint32_t>();
  const std::vector<std::uint32_t> colours = r.vec<std::uint32_t>();
  for (int& n : b.blockOrigin_) n = r.pod<std::int32_t>();
  for (int& n : b.blocks_) n = r.pod<std::int32_t>();
  b.planned_ = r.pod<std::uint8_t>() != 0;
  const bool shaped = colours.size() == 9;
  if (shaped) std::copy(colours.begin(), colours.end(), b.colourStart_.begin());
  if (!shaped || !b.valid(np)) r.fail("holds an inconsistent scatter plan (damaged file)");
  return b;
}

// A plan of sortByBlock's form for this grid and these points (blocks listed
// colour by colour, each of its colour and with points); one that is not
// planned is sorted again before the next scatter.
bool BlockColouring::valid(std::size_t np) const {
  if (!planned_) return true;
  std::size_t nblocks = 1;
  for (int a = 0; a < 3; ++a) {
    if (blockOrigin_[a] < 0 || blockOrigin_[a] >= nodes_[a] ||
        blocks_[a] != (nodes_[a] - blockOrigin_[a] + kBlock - 1) / kBlock)
      return false;
    nblocks *= static_cast<std::size_t>(blocks_[a]);
  }
  const auto& ids = blockId_;
  const auto& starts = blockStart_;
  if (colourStart_[0] != 0 || colourStart_[8] != ids.size() || starts.size() != ids.size() + 1 ||
      starts.front() != 0 || starts.back() != np)
    return false;
  for (std::size_t b = 0; b < ids.size(); ++b)
    if (ids[b] >= nblocks || starts[b + 1] <= starts[b]) return false;
  for (std::size_t c = 0; c < 8; ++c) {
    if (colourStart_[c + 1] < colourStart_[c]) return false;
    for (std::uint32_t b = colourStart_[c]; b < colourStart_[c + 1]; ++b) {
      const std::size_t id = ids[b], bk = id % static_cast<std::size_t>(blocks_[2]),
                        bj = id / static_cast<std::size_t>(blocks_[2]) % static_cast<std::size_t>(blocks_[1]),
                        bi = id / (static_cast<std::size_t>(blocks_[2]) * static_cast<std::size_t>(blocks_[1]));
      if (((bi & 1) | (bj & 1) << 1 | (bk & 1) << 2) != c) return false;
    }
  }
  return true;
}

}  // namespace needlesim::mpm
