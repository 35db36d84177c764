// Which grid cells lie near the other deformable body (near_bodies.hpp):
// the occupancy bits dilated by whole 64-bit words.
#include "needlesim/engines/mpm/near_bodies.hpp"

#include <algorithm>

namespace needlesim::mpm {

namespace {
// Box dilation of the occupancy bits by `reach` cells along each axis: out =
// OR of in over the (2 reach + 1)^3 cells around; rows of rw = 2 W words (W
// per body, bit k), n0 x n1 rows; tmp is scratch of the same size.
void dilateCells(const std::uint64_t* in, std::uint64_t* out, std::uint64_t* tmp, std::size_t n0, std::size_t n1,
                 std::size_t W, std::size_t reach, std::uint64_t lastMask) {
  const std::size_t rw = 2 * W, rows = n0 * n1;
  // Along i (in -> out), then along j (out -> tmp): OR of the rows within reach.
  for (int d = 0; d < 2; ++d) {
    const std::uint64_t* src = d == 0 ? in : out;
    std::uint64_t* dst = d == 0 ? out : tmp;
    for (std::size_t row = 0; row < rows; ++row) {
      const std::size_t idx = d == 0 ? row / n1 : row % n1, n = d == 0 ? n0 : n1, stride = d == 0 ? n1 : 1;
      const std::size_t lo = idx >= reach ? idx - reach : 0, hi = std::min(n - 1, idx + reach);
      std::uint64_t* o = dst + row * rw;
      for (std::size_t w = 0; w < rw; ++w) o[w] = 0;
      for (std::size_t x = lo; x <= hi; ++x) {
        const std::uint64_t* r = src + (row + x * stride - idx * stride) * rw;
        for (std::size_t w = 0; w < rw; ++w) o[w] |= r[w];
      }
    }
  }
  // Along k (tmp -> out): bits shifted by -reach..reach within the row (across word edges).
  for (std::size_t row = 0; row < rows; ++row)
    for (std::size_t body = 0; body < 2; ++body) {
      const std::uint64_t* r = tmp + row * rw + body * W;
      std::uint64_t* o = out + row * rw + body * W;
      for (std::size_t w = 0; w < W; ++w) {
        const std::uint64_t x = r[w], prev = w > 0 ? r[w - 1] : 0, next = w + 1 < W ? r[w + 1] : 0;
        std::uint64_t v = x;
        for (unsigned s = 1; s <= reach; ++s) v |= (x << s) | (prev >> (64 - s)) | (x >> s) | (next << (64 - s));
        o[w] = w + 1 == W ? v & lastMask : v;
      }
    }
}
}  // namespace


// Two bodies: the bit of cell (i, j, k) in row (i, j) of body b is set in
// near when body b has a point within 3 cells (occupied cells dilated by 3
// along each axis). A node both bodies reach lies within 1.5 cells of a point
// of each, so the points that scatter to it are within 3 cells of the other
// body. near1 (dilated by 1) marks the cells whose 27 neighbours hold a point
// of body b: the pair contact's candidates (a pair touches at r < d <= h).
// A row is words() 64-bit words per body (k = bit), so the dilation is shifts
// and ORs of words: serial, the arrays are small (n0 n1 rows of a few words).
// The occupancy comes from the previous step's g2pFinal, which marks the cell
// of each point at its new position; a pass over the points only after
// finalize or a failed step.
void NearBodies::mark(const PointPositions& pts, const std::uint8_t* body, const int* nn) {
  const std::size_t n0 = static_cast<std::size_t>(nn[0]), n1 = static_cast<std::size_t>(nn[1]),
                    n2 = static_cast<std::size_t>(nn[2]);
  const std::size_t W = (n2 + 63) / 64, rw = 2 * W;  // words per row (both bodies)
  words_ = W;
  const std::size_t rows = n0 * n1, total = rows * rw;
  if (occ_.size() != total) {
    occ_.assign(total, 0);
    fresh_ = false;
  }
  near1_.resize(total);
  near_.resize(total);
  nearTmp_.resize(total);
  if (!fresh_) {
    const double invh = 1.0 / pts.h;
    const double ox = pts.origin[0], oy = pts.origin[1], oz = pts.origin[2];
    std::fill(occ_.begin(), occ_.end(), 0);
    for (std::size_t p = 0; p < pts.np; ++p) {
      const double* x = pts.x + pts.stride * p;
      const grid::Cell c = grid::cellAt((x[0] - ox) * invh, (x[1] - oy) * invh, (x[2] - oz) * invh, n1);
      occ_[cellWord(c, body[p], W)] |= cellBit(c);
    }
  }
  const std::uint64_t lastMask = n2 % 64 ? (std::uint64_t{1} << (n2 % 64)) - 1 : ~std::uint64_t{0};
  const std::size_t reach = 1;  // the pair search's reach (a pair touches at r < d <= h)
  dilateCells(occ_.data(), near1_.data(), nearTmp_.data(), n0, n1, W, reach, lastMask);
  dilateCells(near1_.data(), near_.data(), nearTmp_.data(), n0, n1, W, 3 - reach, lastMask);  // 3 cells in all
  std::fill(occ_.begin(), occ_.end(), 0);  // g2pFinal marks the new positions
  fresh_ = false;                       // until g2pFinal has marked them all
}


}  // namespace needlesim::mpm
