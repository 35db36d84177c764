#include "needlesim/fit/least_squares.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <unsupported/Eigen/NonLinearOptimization>

#include "needlesim/core/error.hpp"

namespace needlesim::fit {

namespace {

struct Functor {
  using Scalar = double;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;

  const LsqProblem* prob;
  mutable int evals = 0;
  int inputs() const { return prob->nParams; }
  int values() const { return prob->nResiduals; }

  int operator()(const Eigen::VectorXd& p, Eigen::VectorXd& r) const {
    ++evals;
    r.resize(prob->nResiduals);
    prob->residuals(p, r);
    for (int i = 0; i < r.size(); ++i)
      if (!std::isfinite(r[i])) r[i] = 1e150;  // outside the model's domain: steer away
    return 0;
  }
  // Central differences in the internal parameters (O(h^2) accurate).
  int df(const Eigen::VectorXd& p, Eigen::MatrixXd& J) const {
    J.resize(prob->nResiduals, prob->nParams);
    Eigen::VectorXd rp, rm, q = p;
    for (int k = 0; k < p.size(); ++k) {
      double h = 1e-6 * std::max(1.0, std::abs(p[k]));
      q[k] = p[k] + h;
      (*this)(q, rp);
      q[k] = p[k] - h;
      (*this)(q, rm);
      q[k] = p[k];
      J.col(k) = (rp - rm) / (2 * h);
    }
    return 0;
  }
};

}  // namespace

double aicc(double sse, int n, int k) {
  double s = std::max(sse, 1e-300) / n;
  double a = n * std::log(s) + 2.0 * k;
  if (n - k - 1 > 0) a += 2.0 * k * (k + 1.0) / (n - k - 1.0);
  return a;
}

LsqResult solveLeastSquares(const LsqProblem& prob) {
  if (prob.starts.empty()) throw Error("least squares: no starting point");
  Functor f{&prob};
  LsqResult best;
  best.cost = std::numeric_limits<double>::infinity();
  int totalEvals = 0;
  for (const auto& start : prob.starts) {
    Eigen::VectorXd p = start;
    Eigen::LevenbergMarquardt<Functor> lm(f);
    lm.parameters.maxfev = 400 * (prob.nParams + 1);
    lm.parameters.xtol = 1e-12;
    lm.parameters.ftol = 1e-14;
    int info = lm.minimize(p);
    Eigen::VectorXd r;
    f(p, r);
    double cost = r.squaredNorm();
    totalEvals = f.evals;
    if (cost < best.cost) {
      best.cost = cost;
      best.p = p;
      best.residuals = r;
      // 1: ftol, 2: xtol, 3: both, 4: orthogonality (converged); 5: maxfev; 6-8: tolerances too small
      best.converged = info >= 1 && info <= 4 ? true : (info >= 6 && info <= 8);
      best.message = "minpack info " + std::to_string(info);
    }
  }
  best.evaluations = totalEvals;
  best.theta = prob.physical(best.p);
  const int n = prob.nResiduals, k = prob.nParams;
  best.stdErr = Eigen::VectorXd::Constant(best.theta.size(), std::numeric_limits<double>::quiet_NaN());
  if (n > k) {
    Eigen::MatrixXd J;
    f.df(best.p, J);
    Eigen::MatrixXd D(best.theta.size(), k);
    Eigen::VectorXd q = best.p;
    for (int j = 0; j < k; ++j) {
      double h = 1e-6 * std::max(1.0, std::abs(q[j]));
      q[j] = best.p[j] + h;
      Eigen::VectorXd tp = prob.physical(q);
      q[j] = best.p[j] - h;
      Eigen::VectorXd tm = prob.physical(q);
      q[j] = best.p[j];
      D.col(j) = (tp - tm) / (2 * h);
    }
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeThinV);
    const auto& sv = svd.singularValues();
    if (sv.size() == k && sv[0] > 0 && sv[k - 1] > 1e-10 * sv[0]) {
      Eigen::MatrixXd V = svd.matrixV();
      Eigen::MatrixXd JtJinv = V * sv.cwiseInverse().cwiseAbs2().asDiagonal() * V.transpose();
      double s2 = best.cost / (n - k);
      Eigen::MatrixXd cov = s2 * D * JtJinv * D.transpose();
      for (int i = 0; i < cov.rows(); ++i) best.stdErr[i] = std::sqrt(std::max(0.0, cov(i, i)));
    }
  }
  return best;
}

}  // namespace needlesim::fit
