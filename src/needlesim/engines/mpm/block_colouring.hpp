#pragma once
// The order of the MPM particle passes that lets threads scatter into one
// shared grid without races: the points sorted by grid block (kBlock base
// nodes wide along each axis), the blocks coloured in 2 x 2 x 2 parity, and
// the threads sharing out the blocks of one colour, which touch disjoint
// nodes (docs/models/mpm.md "Parallel scatter").
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "needlesim/io/binary_state.hpp"

namespace needlesim::mpm {

// The block colouring of the scatters for a team of threads: colours with
// points (a barrier between two), blocks with points, threads that get
// points, and the imbalance, the sum over the colours of the largest
// thread's share over the mean share (1: even; the scatters' speed-up is at
// most team / imbalance), and the sorts by block since the set-up.
struct ScatterPlan {
  int colours = 1;
  std::size_t blocks = 0;
  int busyThreads = 1;
  double imbalance = 1.0;
  long long sorts = 0;
};

// Where the points lie: positions x[stride p + d] of np points on a grid of
// nodes[d] nodes along axis d (spacing h from origin), the base node of a
// support at floor((x - origin) / h - shift).
struct PointPositions {
  const double* x;
  std::size_t stride;
  std::size_t np;
  const double* origin;
  double h;
  double shift;
};

// Race-free scatter (3D block colouring, sort): the grid is cut, from the
// points' lowest base node on (so that few blocks are partly filled), into
// blocks of kBlock base nodes along each axis, block (bi, bj, bk) of colour
// (bi & 1) | (bj & 1) << 1 | (bk & 1) << 2; order() visits the points colour
// by colour, block by block (creation order within a block); listed block b
// is order[blockStart[b], blockStart[b + 1]), of grid block blockId[b];
// colour c is listed blocks [colourStart[c], colourStart[c + 1]). A point
// whose base node leaves its block by more than one node asks for a re-sort
// before the next scatter (invalidate). One thread keeps the creation order
// in one pass.
class BlockColouring {
 public:
  static constexpr int kBlock = 4;

  // The set-up: np points in creation order on a grid of nodes[3] nodes.
  void reset(std::size_t np, const int* nodes, int threads);
  // Before each scatter: sort the points by block when nothing is planned
  // (one thread: never).
  void plan(const PointPositions& pts) {
    if (threads_ > 1 && !planned_) sortByBlock(pts);
  }
  void invalidate() { planned_ = false; }
  bool blocked() const { return threads_ > 1; }

  const std::uint32_t* order() const { return order_.data(); }
  // The points thread t of a team of T visits in pass `colour` (0 .. 7, a
  // barrier between two): a run of whole blocks of that colour.
  std::pair<std::size_t, std::size_t> colourShare(int t, int T, int colour) const;
  bool colourHasPoints(int c) const {
    return threads_ == 1 ? c == 0
                         : colourStart_[static_cast<std::size_t>(c)] != colourStart_[static_cast<std::size_t>(c) + 1];
  }
  int lastColour() const {
    int last = 0;
    for (int c = 1; c < 8; ++c)
      if (colourHasPoints(c)) last = c;
    return last;
  }
  // The listed block of scatter entry q (blocked only), its end, and the base
  // nodes its points may have at the start of a scatter (its block's, widened
  // by one node on each side).
  std::size_t blockOf(std::size_t q) const;
  std::size_t blockEnd(std::size_t listed) const { return blockStart_[listed + 1]; }
  void blockBounds(std::size_t listed, int* lo, int* hi) const;

  ScatterPlan stats(int team, std::size_t np) const;
  long long sorts() const { return sorts_; }

  // Checkpoints: the order and plan; read checks them against this set-up
  // (np points, the grid of reset) and returns the loaded colouring.
  void save(io::BinaryWriter& w) const;
  BlockColouring read(io::BinaryReader& r, std::size_t np) const;

 private:
  void sortByBlock(const PointPositions& pts);
  std::vector<std::uint32_t> sortPointsByKey(const std::vector<std::uint32_t>& key, std::size_t nkeys);
  bool valid(std::size_t np) const;

  int threads_ = 1;
  int nodes_[3] = {0, 0, 0};
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> blockStart_, blockId_;
  std::array<std::uint32_t, 9> colourStart_{};
  int blockOrigin_[3] = {0, 0, 0};  // base node where block 0 starts along each axis (the points' lowest)
  int blocks_[3] = {0, 0, 0};       // blocks from there to the grid's end along each axis
  bool planned_ = false;
  long long sorts_ = 0;
};

}  // namespace needlesim::mpm
