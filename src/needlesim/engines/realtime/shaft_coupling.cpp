#include "needlesim/engines/realtime/shaft_coupling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "needlesim/core/error.hpp"
#include "needlesim/needle/beam_element.hpp"

namespace needlesim::realtime {

using needle::cantileverDeflection;
using needle::cantileverSlope;

namespace {
// A coupled node is released only once it lies this far ahead of the tip, so a node
// dragged along right at the tip does not flicker between coupled and free.
constexpr double kReleaseGap = 1e-4;  // m
}  // namespace

ShaftCoupling::ShaftCoupling(ShaftSettings s) : cfg_(std::move(s)) {
  lat_ = cfg_.lateral;
  comps_ = 1 + lat_;
  P_ = static_cast<int>(cfg_.path_s.size());
  const auto P = static_cast<std::size_t>(P_), D = static_cast<std::size_t>(comps_ * P_);
  status_.assign(P, FrictionStatus::Stick);
  offset_.assign(P * static_cast<std::size_t>(lat_), 0.0);
  channel_.assign(P * static_cast<std::size_t>(lat_), std::numeric_limits<double>::quiet_NaN());
  lambda_.assign(P * static_cast<std::size_t>(lat_), 0.0);
  sigma_.assign(P, 0.0); ell_.assign(P, 0.0); pos_.assign(P, 0.0); axial_prev_.assign(P, 0.0);
  idx_.assign(D, 0);
  order_.assign(P, 0);
  fK_.setZero(comps_ * P_); f_.setZero(comps_ * P_); y_.setZero(comps_ * P_);
  rhs_.setZero(comps_ * P_); x_.setZero(comps_ * P_); un_.setZero(comps_ * P_);
  H_.setZero(comps_ * P_, comps_ * P_);
}

double ShaftCoupling::deflection(int j, double sigma) const {
  const double EI = cfg_.EI, L = cfg_.length;
  double w = nl_.Q[j] * cantileverDeflection(sigma, L, EI);
  for (int i = 0; i < k_; ++i) w -= tieLoad(j, i) * cantileverDeflection(sigma, sigma_[static_cast<std::size_t>(i)], EI);
  return w;
}

double ShaftCoupling::slope(int j, double sigma) const {
  const double EI = cfg_.EI, L = cfg_.length;
  double th = nl_.Q[j] * cantileverSlope(sigma, L, EI);
  for (int i = 0; i < k_; ++i) th -= tieLoad(j, i) * cantileverSlope(sigma, sigma_[static_cast<std::size_t>(i)], EI);
  return th;
}

void ShaftCoupling::couple(bool entered, double reach, const Eigen::VectorXd& pu) {
  int k = 0;
  if (entered)
    while (k < P_ && cfg_.path_s[static_cast<std::size_t>(k)] + pu[comps_ * k] <= reach + (k < k_ ? kReleaseGap : 0.0)) ++k;
  for (int i = k_; i < k; ++i) {
    const double p = cfg_.path_s[static_cast<std::size_t>(i)] + pu[comps_ * i];
    for (int j = 0; j < lat_; ++j) {
      const auto ij = static_cast<std::size_t>(i * lat_ + j);
      offset_[ij] = std::isnan(channel_[ij]) ? pu[comps_ * i + 1 + j] - lateralAt(j, p) : -channel_[ij];
    }
    status_[static_cast<std::size_t>(i)] = FrictionStatus::Stick;
  }
  for (int i = k; i < k_; ++i)
    for (int j = 0; j < lat_; ++j) lambda_[static_cast<std::size_t>(i * lat_ + j)] = 0.0;
  k_ = k;
}

// Current axial positions of the coupled nodes, their tributary shaft lengths in contact and
// arc positions from the base. The lengths follow the nodes' current order along the axis (a
// node dragged past others keeps its share): boundaries halfway between neighbours in that
// order, clamped to the tissue (entry .. tip or exit face), so they add up to the shaft in
// contact exactly.
void ShaftCoupling::measure(double s_tip, double s_exit, const Eigen::VectorXd& pu) {
  const int k = k_;
  for (int i = 0; i < k; ++i) pos_[static_cast<std::size_t>(i)] = cfg_.path_s[static_cast<std::size_t>(i)] + pu[comps_ * i];
  for (int i = 0; i < k; ++i) {  // insertion sort: the nodes are nearly in order, and it allocates nothing
    int r = i;
    for (; r > 0 && pos_[static_cast<std::size_t>(order_[static_cast<std::size_t>(r - 1)])] > pos_[static_cast<std::size_t>(i)]; --r)
      order_[static_cast<std::size_t>(r)] = order_[static_cast<std::size_t>(r - 1)];
    order_[static_cast<std::size_t>(r)] = i;
  }
  const double top = std::min(s_tip, s_exit), in = std::min(cfg_.entry_s, top);
  for (int r = 0; r < k; ++r) {
    const auto p = static_cast<std::size_t>(order_[static_cast<std::size_t>(r)]);
    const double prev = r == 0 ? 0.0 : pos_[static_cast<std::size_t>(order_[static_cast<std::size_t>(r - 1)])];
    const double next = r + 1 == k ? 0.0 : pos_[static_cast<std::size_t>(order_[static_cast<std::size_t>(r + 1)])];
    const double lo = r == 0 ? in : std::clamp(0.5 * (prev + pos_[p]), in, top);
    const double hi = r + 1 == k ? top : std::clamp(0.5 * (pos_[p] + next), in, top);
    ell_[p] = hi - lo;
    sigma_[p] = std::max((pos_[p] - nl_.sB) / nl_.cosphi, 0.0);
  }
}

// Active set on the axial status of each coupled node (eq 3.23), to a fixed point.
int ShaftCoupling::solve(const TissueDynamics& t, const AxialMotion& mo, double dt) {
  int it = 0;
  for (; it < cfg_.max_iterations; ++it) {
    addKnownLoads(t);
    const int m = assemble(t, mo, dt);
    if (!solveSmall(m)) throw SolverError(cfg_.engine + ": the coupling system is not positive definite");
    for (int a = 0; a < m; ++a) f_[idx_[static_cast<std::size_t>(a)]] += x_[a];
    // In the second half of the iterations a node may only leave stick (to hold, then slip), never
    // return to it: coupled nodes can otherwise pass the stick force between them in a cycle
    // (seen when a 3D block's shaft restarts after a pause) and end on an inconsistent set.
    if (!updateStatus(t, mo, 2 * it >= cfg_.max_iterations)) break;
  }
  for (int i = 0; i < P_; ++i) {
    for (int j = 0; j < lat_ && i < k_; ++j) lambda_[static_cast<std::size_t>(i * lat_ + j)] = f_[comps_ * i + 1 + j];
    axial_prev_[static_cast<std::size_t>(i)] = i < k_ ? shaftAxialLoad(i) : 0.0;
  }
  return it + 1;
}

// Known loads (press, cutting, held static friction, undamped slip) into f_, and the
// path displacement they give, y = u0 + S f_known.
void ShaftCoupling::addKnownLoads(const TissueDynamics& t) {
  const auto& S = t.pathCompliance();
  f_ = fK_;
  using S_ = FrictionStatus;
  for (int i = 0; i < k_; ++i) {
    const auto st = status_[static_cast<std::size_t>(i)];
    const double l = ell_[static_cast<std::size_t>(i)];
    const auto& fr = cfg_.friction[static_cast<std::size_t>(i)];
    if (!(l > 1e-9)) continue;
    const bool pos = st == S_::HoldPos || st == S_::SlipPos;
    if (st == S_::HoldPos || st == S_::HoldNeg) f_[comps_ * i] += contact::karnoppStaticLimit(fr, pos) * l;
    if ((st == S_::SlipPos || st == S_::SlipNeg) && !(contact::karnoppDamping(fr, pos) * l > 1e-12))
      f_[comps_ * i] += contact::karnoppSliding(fr, pos, 0.0) * l;
  }
  y_ = t.predictedPath();
  for (int l = 0; l < f_.size(); ++l)
    if (f_[l] != 0.0) y_.noalias() += f_[l] * S.col(l);
}

// Whether node i's axial load is an unknown of the system (stick or damped slip).
bool ShaftCoupling::axialUnknown(int i) const {
  const auto st = status_[static_cast<std::size_t>(i)];
  const double l = ell_[static_cast<std::size_t>(i)];
  const auto& fr = cfg_.friction[static_cast<std::size_t>(i)];
  if (!(l > 1e-9)) return false;  // no shaft in contact (dragged out of the tissue): no axial load
  const bool slip = st == FrictionStatus::SlipPos || st == FrictionStatus::SlipNeg;
  return st == FrictionStatus::Stick || (slip && contact::karnoppDamping(fr, st == FrictionStatus::SlipPos) * l > 1e-12);
}

// The lower triangle of H_'s leading m x m block: S on the unknown slots, the interface
// compliance on the diagonal, the needle flexibility between ties of one plane (eq 3.12).
// Column by column, so it writes (and reads S) down contiguous columns; solveSmall reads
// the lower triangle only.
void ShaftCoupling::assembleMatrix(const Eigen::MatrixXd& S, int m) {
  const double EI = cfg_.EI;
  const bool soft = !cfg_.interface_compliance.empty();
  for (int b = 0; b < m; ++b) {
    const int ib = idx_[static_cast<std::size_t>(b)], cb = ib % comps_;
    const double sb = sigma_[static_cast<std::size_t>(ib / comps_)];
    double* col = &H_(0, b);
    for (int a = b; a < m; ++a) {
      const int ia = idx_[static_cast<std::size_t>(a)];
      double h = S(ia, ib);
      if (a == b && soft) h += cfg_.interface_compliance[static_cast<std::size_t>(ia)];
      if (cb > 0 && cb == ia % comps_) h += cantileverDeflection(sigma_[static_cast<std::size_t>(ia / comps_)], sb, EI);
      col[a] = h;
    }
  }
}

// The SPD system on the unknown slots (all lateral ties, axial stick and damped slip):
// H_ = S + needle flexibility between ties of one bending plane (eq 3.12), rhs_ from the
// constraints. Returns its size.
int ShaftCoupling::assemble(const TissueDynamics& t, const AxialMotion& mo, double dt) {
  const auto& S = t.pathCompliance();
  const auto& c = t.coefficients();
  const Eigen::VectorXd &pu = t.pathU(), &pv = t.pathV(), &pa = t.pathA();
  const double gam = c.gamma(), EI = cfg_.EI;
  int m = 0;
  for (int i = 0; i < k_; ++i) {
    for (int j = 0; j < lat_; ++j) idx_[static_cast<std::size_t>(m++)] = comps_ * i + 1 + j;
    if (axialUnknown(i)) idx_[static_cast<std::size_t>(m++)] = comps_ * i;
  }
  assembleMatrix(S, m);
  for (int a = 0; a < m; ++a) {
    const int ia = idx_[static_cast<std::size_t>(a)], na = ia / comps_, ca = ia % comps_;
    const auto p = static_cast<std::size_t>(na);
    // axial: the interface keeps the stretch of the shaft's last load on the point
    const double kept = ca == 0 && !cfg_.interface_compliance.empty() ? cfg_.interface_compliance[static_cast<std::size_t>(ia)] * axial_prev_[p] : 0.0;
    if (ca > 0) {  // lateral tie: u_j = needle lateral + offset
      const int j = ca - 1;
      rhs_[a] = rigidLateral(j, pos_[p]) + nl_.Q[j] * cantileverDeflection(sigma_[p], cfg_.length, EI) +
                offset_[p * static_cast<std::size_t>(lat_) + static_cast<std::size_t>(j)] - y_[ia];
    } else if (status_[p] == FrictionStatus::Stick) {  // axial: moves with the needle
      rhs_[a] = pu[ia] + mo.ds - y_[ia] + kept;
    } else {  // implicit slip: mu = r - cc u (eq 3.23 slip branches, Newmark velocity v = e + a1 u)
      const auto& fr = cfg_.friction[p];
      const bool posv = status_[p] == FrictionStatus::SlipPos;
      const double e = pv[ia] + dt * (1.0 - gam) * pa[ia] - c.a1 * pu[ia] - dt * gam * (c.a2 * pv[ia] + c.a3 * pa[ia]);
      const double r = ell_[p] * contact::karnoppSliding(fr, posv, mo.v_ax - e);
      const double cc = ell_[p] * contact::karnoppDamping(fr, posv) * c.a1;
      H_(a, a) += 1.0 / cc;
      rhs_[a] = r / cc - y_[ia] + kept;
    }
  }
  return m;
}

// New axial path velocity of each coupled node and its Karnopp status update (eq 3.23);
// `monotone`: no return to stick. Returns whether any status changed.
bool ShaftCoupling::updateStatus(const TissueDynamics& t, const AxialMotion& mo, bool monotone) {
  const auto& S = t.pathCompliance();
  const auto& c = t.coefficients();
  const Eigen::VectorXd& u0 = t.predictedPath();
  const Eigen::VectorXd &pu = t.pathU(), &pv = t.pathV(), &pa = t.pathA();
  bool changed = false;
  un_ = u0;  // u0 + S f, a column of S at a time (each entry sums in the same order as row by row)
  for (int l = 0; l < f_.size(); ++l)
    if (f_[l] != 0.0) un_.noalias() += f_[l] * S.col(l);
  for (int i = 0; i < k_; ++i) {
    const auto p = static_cast<std::size_t>(i);
    const int ia = comps_ * i;
    const double un = un_[ia];
    const double vn = c.velocity(pv[ia], pa[ia], c.acceleration(un, pu[ia], pv[ia], pa[ia]));
    // the shaft's load per length: the known tip loads on the node are not friction
    const double Fa = ell_[p] > 0.0 ? (f_[ia] - fK_[ia]) / ell_[p] : 0.0;
    const FrictionStatus next = contact::karnoppNext(status_[p], cfg_.friction[p], Fa, mo.v_ax - vn);
    if (monotone && next == FrictionStatus::Stick) continue;
    if (next != status_[p]) { status_[p] = next; changed = true; }
  }
  return changed;
}

// In-place Cholesky solve of the leading m x m block of H_ (its lower triangle) with rhs_ -> x_.
// Left-looking by columns: column j takes the updates of columns 0 .. j-1 in turn (four at a
// time) as contiguous axpys (vectorised, cache-friendly), and each entry subtracts its terms in
// the same order as the dot-product form L_ij = (A_ij - sum_k L_ik L_jk) / L_jj.
bool ShaftCoupling::solveSmall(int m) {
  double* A = H_.data();
  const Eigen::Index ld = H_.outerStride();
  for (int j = 0; j < m; ++j) {
    double* cj = A + j * ld;
    int k = 0;
    for (; k + 4 <= j; k += 4) {  // four columns per pass over column j (its entries stay in registers)
      const double *c0 = A + k * ld, *c1 = c0 + ld, *c2 = c1 + ld, *c3 = c2 + ld;
      const double l0 = c0[j], l1 = c1[j], l2 = c2[j], l3 = c3[j];
      for (int i = j; i < m; ++i) cj[i] = cj[i] - c0[i] * l0 - c1[i] * l1 - c2[i] * l2 - c3[i] * l3;
    }
    for (; k < j; ++k) {
      const double* ck = A + k * ld;
      const double ljk = ck[j];
      for (int i = j; i < m; ++i) cj[i] -= ck[i] * ljk;
    }
    if (!(cj[j] > 0.0)) return false;
    const double d = std::sqrt(cj[j]);
    cj[j] = d;
    for (int i = j + 1; i < m; ++i) cj[i] /= d;
  }
  double* x = x_.data();
  for (int i = 0; i < m; ++i) x[i] = rhs_[i];
  for (int k = 0; k < m; ++k) {  // L z = rhs, by columns
    const double* ck = A + k * ld;
    x[k] /= ck[k];
    for (int i = k + 1; i < m; ++i) x[i] -= ck[i] * x[k];
  }
  for (int i = m - 1; i >= 0; --i) {  // L^T x = z
    const double* ci = A + i * ld;
    double s = x[i];
    for (int k = i + 1; k < m; ++k) s -= ci[k] * x[k];
    x[i] = s / ci[i];
  }
  return true;
}

}  // namespace needlesim::realtime
