#pragma once
// Two deformable bodies: per grid cell whether the other body is near, so
// that only the points near it write the gradient records (p2g) and enter
// the pair contact's search (penalty_contact.hpp). Bits per (i, j) row, per
// body words() 64-bit words, bit k of cell (i, j, k).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "needlesim/engines/mpm/block_colouring.hpp"
#include "needlesim/engines/mpm/grid_kernels.hpp"

namespace needlesim::mpm {

// The word of cell c of body b in the bit rows (W words per body and row,
// both bodies in a row), and its bit.
inline std::size_t cellWord(grid::Cell c, std::size_t b, std::size_t W) { return (2 * c.row + b) * W + c.k / 64; }
inline std::uint64_t cellBit(grid::Cell c) { return std::uint64_t{1} << (c.k % 64); }

class NearBodies {
 public:
  // Before each scatter: the cells near each body from the occupancy (the
  // points of body[p] at pts, on a grid of nn nodes per axis).
  void mark(const PointPositions& pts, const std::uint8_t* body, const int* nn);
  const std::uint64_t* near() const { return near_.data(); }    // within 3 cells
  const std::uint64_t* near1() const { return near1_.data(); }  // within the 27 cells around
  std::size_t words() const { return words_; }
  // The occupancy g2pFinal marks at the new positions (null before the first mark);
  // fresh: every point marked its cell, so the next mark needs no pass over the points.
  std::uint64_t* occupancy() { return occ_.empty() ? nullptr : occ_.data(); }
  void setFresh(bool fresh) { fresh_ = fresh; }

 private:
  std::vector<std::uint64_t> occ_, near1_, near_, nearTmp_;
  std::size_t words_ = 1;
  bool fresh_ = false;
};

}  // namespace needlesim::mpm
