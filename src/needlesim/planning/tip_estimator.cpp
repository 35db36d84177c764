// Gauss-Newton MAP estimate of the entry pose and curvature scale (tip_estimator.hpp).
#include "needlesim/planning/tip_estimator.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace needlesim::planning {

TipEstimator::TipEstimator(const Pose& nominal, const std::array<double, 7>& sd, double noise)
    : nominal_(nominal), noise_(std::max(noise, 1e-9)) {
  // a spread of 0 is a parameter known exactly: a tight prior keeps it there
  for (int k = 0; k < 7; ++k) sd_[k] = std::max(sd[k], 1e-9);
}

double TipEstimator::curvatureScale() const { return std::exp(theta_[6]); }

Channel TipEstimator::replay(const Params& th, std::vector<Vec3>* predicted) const {
  Pose g = nominal_;
  g.p += Vec3(th[0], th[1], th[2]);
  const Vec3 w(th[3], th[4], th[5]);
  if (w.norm() > 0) g.R = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * g.R;
  Channel channel(g, std::exp(th[6]));
  std::size_t m = 0;
  for (std::size_t i = 0; i <= arcs_.size(); ++i) {
    while (predicted && m < at_.size() && at_[m] == i) predicted->push_back(channel.tip().p), ++m;
    if (i < arcs_.size()) channel.follow(arcs_[i]);
  }
  return channel;
}

// Measurement residuals over the noise, then the prior's: each parameter over its spread.
std::vector<double> TipEstimator::residuals(const Params& th) const {
  std::vector<Vec3> predicted;
  replay(th, &predicted);
  std::vector<double> r;
  r.reserve(3 * predicted.size() + 7);
  for (std::size_t i = 0; i < predicted.size(); ++i)
    for (int a = 0; a < 3; ++a) r.push_back((predicted[i][a] - tips_[i][a]) / noise_);
  for (int k = 0; k < 7; ++k) r.push_back(th[k] / sd_[k]);
  return r;
}

void TipEstimator::measured(const Vec3& tip) {
  at_.push_back(arcs_.size());
  tips_.push_back(tip);
  for (int iteration = 0; iteration < 3; ++iteration) {
    const std::vector<double> r0 = residuals(theta_);
    Eigen::MatrixXd J(r0.size(), 7);
    for (int k = 0; k < 7; ++k) {
      Params th = theta_;
      const double h = 1e-4 * sd_[k];
      th[k] += h;
      const std::vector<double> r1 = residuals(th);
      for (std::size_t i = 0; i < r0.size(); ++i) J(static_cast<Eigen::Index>(i), k) = (r1[i] - r0[i]) / h;
    }
    const Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(r0.data(), static_cast<Eigen::Index>(r0.size()));
    const Eigen::Matrix<double, 7, 1> step = (J.transpose() * J).ldlt().solve(-J.transpose() * r);
    for (int k = 0; k < 7; ++k) theta_[k] += step[k];
    if (step.norm() < 1e-9) break;
  }
}

}  // namespace needlesim::planning
