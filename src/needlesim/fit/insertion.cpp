#include "needlesim/fit/insertion.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "needlesim/core/error.hpp"

namespace needlesim::fit {

namespace {

std::string fmtNum(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

const double kNaN = std::numeric_limits<double>::quiet_NaN();

// integral of y dx over [a, b] by the trapezoid rule on the samples (linear interpolation at the ends)
double integrate(const std::vector<double>& x, const std::vector<double>& y, double a, double b) {
  auto interp = [&](double t) {
    if (t <= x.front()) return y.front();
    if (t >= x.back()) return y.back();
    auto it = std::upper_bound(x.begin(), x.end(), t);
    std::size_t j = static_cast<std::size_t>(it - x.begin());
    double w = (t - x[j - 1]) / (x[j] - x[j - 1]);
    return y[j - 1] + w * (y[j] - y[j - 1]);
  };
  double s = 0, prevX = a, prevY = interp(a);
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (x[i] <= a) continue;
    if (x[i] >= b) break;
    s += 0.5 * (prevY + y[i]) * (x[i] - prevX);
    prevX = x[i];
    prevY = y[i];
  }
  s += 0.5 * (prevY + interp(b)) * (b - prevX);
  return s;
}

}  // namespace

std::vector<InsertionLog> readInsertionLogs(const io::CsvData& csv, double speedOverride) {
  int cz = csv.require({"depth", "position", "displacement", "insertion depth", "tip depth"}, units::dim::Length,
                       "needle depth");
  int cf = csv.require({"force", "axial force", "insertion force"}, units::dim::Force, "insertion force");
  int ct = csv.find({"time", "t"});
  int cv = csv.find({"speed", "velocity", "insertion speed"});
  if (ct >= 0) csv.checkDim(ct, units::dim::Time, "time");
  if (cv >= 0) csv.checkDim(cv, units::dim::Velocity, "speed");
  const auto& z = csv.col(cz);
  const auto& f = csv.col(cf);
  // group rows by speed (one group if there is no speed column)
  std::vector<std::pair<double, std::vector<std::size_t>>> groups;
  for (std::size_t i = 0; i < csv.rows(); ++i) {
    double v = cv >= 0 ? csv.col(cv)[i] : 0.0;
    auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) {
      return std::abs(g.first - v) <= 1e-9 * std::max(std::abs(v), 1e-12);
    });
    if (it == groups.end()) {
      groups.push_back({v, {}});
      it = groups.end() - 1;
    }
    it->second.push_back(i);
  }
  std::vector<InsertionLog> out;
  for (const auto& [v, rows] : groups) {
    InsertionLog log;
    log.file = csv.file;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      std::size_t i = rows[k];
      if (k > 0 && z[i] < z[rows[k - 1]])
        throw InputError({csv.file, csv.lines[i], csv.columns[cz].headerColumn}, "column '" + csv.columns[cz].name + "'",
                         fmtNum(z[i]), "the depth decreases (line " + std::to_string(csv.lines[rows[k - 1]]) +
                                           " has " + fmtNum(z[rows[k - 1]]) + " m); retraction is not analysed",
                         "the insertion phase only, with non-decreasing depth");
      log.depth.push_back(z[i]);
      log.force.push_back(f[i]);
      log.lines.push_back(csv.lines[i]);
    }
    if (speedOverride > 0) {
      log.speed = speedOverride;
    } else if (cv >= 0) {
      log.speed = v;
    } else if (ct >= 0 && rows.size() >= 2) {
      double mt = 0, mz = 0;
      for (std::size_t i : rows) {
        mt += csv.col(ct)[i];
        mz += z[i];
      }
      mt /= rows.size();
      mz /= rows.size();
      double num = 0, den = 0;
      for (std::size_t i : rows) {
        num += (csv.col(ct)[i] - mt) * (z[i] - mz);
        den += (csv.col(ct)[i] - mt) * (csv.col(ct)[i] - mt);
      }
      log.speed = den > 0 ? num / den : 0.0;
    }
    out.push_back(std::move(log));
  }
  return out;
}

Puncture detectPuncture(const InsertionLog& log, double dropFraction) {
  Puncture p;
  // Noise level from the median absolute first difference (robust to the drop itself):
  // for white noise s, |diff| has median 0.954 s.
  double noise = 0.0;
  if (log.force.size() > 3) {
    std::vector<double> d;
    for (std::size_t i = 1; i < log.force.size(); ++i) d.push_back(std::abs(log.force[i] - log.force[i - 1]));
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    noise = d[d.size() / 2] / 0.954;
  }
  double peak = -std::numeric_limits<double>::infinity();
  std::size_t ip = 0;
  for (std::size_t i = 0; i < log.force.size(); ++i) {
    if (log.force[i] > peak) {
      peak = log.force[i];
      ip = i;
    } else if (peak > 0 && peak - log.force[i] > std::max(dropFraction * peak, 6.0 * noise)) {
      p.found = true;
      break;
    }
  }
  if (!p.found) return p;
  p.depth = log.depth[ip];
  p.force = peak;
  p.line = log.lines.empty() ? 0 : log.lines[ip];
  double fmin = peak;
  for (std::size_t i = ip; i < log.force.size() && log.depth[i] <= p.depth + 0.1 * std::max(p.depth, 1e-3); ++i)
    fmin = std::min(fmin, log.force[i]);
  p.drop = peak - fmin;
  double num = 0, den = 0;
  for (std::size_t i = 0; i <= ip; ++i)
    if (log.depth[i] > 0) {
      num += log.depth[i] * log.force[i];
      den += log.depth[i] * log.depth[i];
    }
  p.stiffness = den > 0 ? num / den : 0.0;
  return p;
}

ToughnessResult ruptureToughness(const InsertionLog& log, const ToughnessOptions& opt) {
  SourceLocation where{log.file, 0, 0};
  if (!(opt.diameter > 0))
    throw InputError(where, "--needle-diameter", fmtNum(opt.diameter), "the needle diameter is needed for G_c (A = pi d^2/4)",
                     "a length > 0, e.g. --needle-diameter '0.71 mm'");
  if (!(opt.shaftLength > 0))
    throw InputError(where, "--thickness", fmtNum(opt.shaftLength),
                     "the tissue thickness L2 (shaft length inside once the tip exits) is needed for G_c",
                     "a length > 0, e.g. --thickness '102 mm'");
  if (log.depth.size() < 4)
    throw InputError({log.file, log.lines.empty() ? 0 : log.lines.back(), 0}, "data",
                     std::to_string(log.depth.size()) + " points", "too few points for a toughness analysis",
                     "at least 4 points");
  ToughnessResult r;
  r.area = std::numbers::pi / 4 * opt.diameter * opt.diameter;
  r.L2 = opt.shaftLength;
  // F2: mean force once the tip is out (depth beyond L2 by 2 %).
  double sum = 0;
  int cnt = 0;
  for (std::size_t i = 0; i < log.depth.size(); ++i)
    if (log.depth[i] > 1.02 * r.L2) {
      sum += log.force[i];
      ++cnt;
    }
  if (cnt < 2)
    throw InputError({log.file, log.lines.back(), 0}, "depth", fmtNum(log.depth.back()),
                     "the log must continue after the tip exits the tissue to measure the friction force F2 (seed 002 eq 15)",
                     "at least 2 points deeper than 1.02 x the thickness " + fmtNum(r.L2) + " m");
  r.F2 = sum / cnt;
  r.frictionPerLength = r.F2 / r.L2;
  double a = opt.windowStart;
  if (a < 0) {
    Puncture p = detectPuncture(log);
    a = p.found && p.depth < r.L2 ? p.depth : 0.0;
  }
  double L1 = opt.windowLength > 0 ? opt.windowLength : r.L2 - a;
  if (!(L1 > 0) || a + L1 > r.L2 * (1 + 1e-9))
    throw InputError(where, "--window", fmtNum(a) + " + " + fmtNum(L1),
                     "the L1 window must lie where the tip is inside the tissue", "0 <= start < start + L1 <= thickness");
  r.windowStart = a;
  r.L1 = L1;
  const double b = a + L1;
  r.Gftc = integrate(log.depth, log.force, a, b) / r.area;  // seed 004 eq 11
  if (opt.literalEq12)
    r.Gft = r.F2 * L1 / r.L2 * L1 / r.area;  // F2' = F2 L1/L2 constant over L1
  else
    r.Gft = r.frictionPerLength * 0.5 * (b * b - a * a) / r.area;  // friction k L with the inserted length L
  r.Gc = r.Gftc - r.Gft;  // seed 004 eq 13
  return r;
}

double cohesiveStrength(double Gc, double deltaC) { return 2.0 * Gc / deltaC; }

double interactionStiffnessFromModulus(double E, double d, double h) {
  double a = std::numbers::pi * d * d / 4, c = std::numbers::pi * d;
  return E * a / (h * c);  // seed 002 eq 11
}

double interactionStiffness(double C10, double d, double h) { return 1.5 * C10 * d / h; }  // seed 002 eq 13

FrictionFit frictionFromSummaries(const std::vector<FrictionRow>& rows, const std::string& file) {
  const int n = static_cast<int>(rows.size());
  if (n < 2)
    throw InputError({file, rows.empty() ? 0 : rows.back().line, 0}, "data", std::to_string(n) + " rows",
                     "friction and damping need at least two speeds", "two or more rows at different speeds");
  Eigen::MatrixXd X(n, 2);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    if (!(rows[i].length > 0))
      throw InputError({file, rows[i].line, 0}, "length", fmtNum(rows[i].length), "the contact length must be > 0",
                       "a length > 0");
    X(i, 0) = rows[i].length;
    X(i, 1) = rows[i].length * rows[i].speed;
    y[i] = rows[i].force - rows[i].cutting;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X);
  if (qr.rank() < 2)
    throw InputError({file, rows.back().line, 0}, "speed", fmtNum(rows.back().speed),
                     "all rows have the same speed, so friction C and damping b cannot be separated",
                     "rows at two or more different speeds");
  Eigen::VectorXd beta = qr.solve(y);
  FrictionFit fit;
  fit.C = beta[0];
  fit.b = beta[1];
  fit.n = n;
  Eigen::VectorXd res = X * beta - y;
  fit.rmse = std::sqrt(res.squaredNorm() / n);
  fit.seC = fit.seB = kNaN;
  if (n > 2) {
    Eigen::MatrixXd cov = res.squaredNorm() / (n - 2) * (X.transpose() * X).inverse();
    fit.seC = std::sqrt(cov(0, 0));
    fit.seB = std::sqrt(cov(1, 1));
  }
  for (const auto& r : rows) {
    fit.speeds.push_back(r.speed);
    fit.cutting.push_back(r.cutting);
    fit.seCutting.push_back(kNaN);
  }
  return fit;
}

std::vector<FrictionRow> readFrictionSummaries(const io::CsvData& csv) {
  int cv = csv.require({"speed", "velocity"}, units::dim::Velocity, "insertion speed");
  int cf = csv.require({"force", "measured force"}, units::dim::Force, "measured force");
  int cc = csv.require({"cutting force", "cutting"}, units::dim::Force, "cutting force");
  int cl = csv.require({"length", "contact length", "shaft length"}, units::dim::Length, "shaft contact length");
  std::vector<FrictionRow> rows;
  for (std::size_t i = 0; i < csv.rows(); ++i)
    rows.push_back({csv.col(cv)[i], csv.col(cf)[i], csv.col(cc)[i], csv.col(cl)[i], csv.lines[i]});
  return rows;
}

namespace {

// The distinct insertion speeds of the logs, in order of first appearance (at least two).
std::vector<double> distinctSpeeds(const std::vector<InsertionLog>& logs) {
  std::vector<double> speeds;
  for (const auto& l : logs) {
    if (!(l.speed > 0))
      throw InputError({l.file, l.lines.empty() ? 0 : l.lines.front(), 0}, "speed", fmtNum(l.speed),
                       "the insertion speed of this log is unknown or not positive",
                       "a 'speed [mm/s]' or 'time [s]' column, or --speed");
    if (std::none_of(speeds.begin(), speeds.end(), [&](double s) { return std::abs(s - l.speed) <= 1e-6 * s; }))
      speeds.push_back(l.speed);
  }
  if (speeds.size() < 2)
    throw InputError({logs.front().file, 0, 0}, "speed", fmtNum(speeds.front()),
                     "all logs have the same speed, so friction C and damping b cannot be separated",
                     "logs at two or more different speeds");
  return speeds;
}

struct FrictionPoint {
  double z, f, v;
  int run;
};

// The points after each log's puncture, also kept per run in fit.depth and fit.measured.
std::vector<FrictionPoint> postPuncturePoints(const std::vector<InsertionLog>& logs, FrictionFit& fit) {
  std::vector<FrictionPoint> pts;
  fit.depth.resize(logs.size());
  fit.measured.resize(logs.size());
  for (std::size_t r = 0; r < logs.size(); ++r) {
    const auto& l = logs[r];
    Puncture p = detectPuncture(l);
    double z0 = 0;
    if (p.found) {
      // skip the relaxation right after the puncture: start at the force minimum following the peak
      std::size_t i = 0;
      while (i < l.depth.size() && l.depth[i] < p.depth) ++i;
      std::size_t imin = i;
      for (std::size_t j = i; j < l.depth.size() && l.depth[j] <= p.depth + 0.1 * std::max(p.depth, 1e-3); ++j)
        if (l.force[j] < l.force[imin]) imin = j;
      z0 = l.depth[imin];
    }
    for (std::size_t i = 0; i < l.depth.size(); ++i)
      if (l.depth[i] > 0 && l.depth[i] >= z0) {
        pts.push_back({l.depth[i], l.force[i], l.speed, static_cast<int>(r)});
        fit.depth[r].push_back(l.depth[i]);
        fit.measured[r].push_back(l.force[i]);
      }
  }
  return pts;
}

// Columns: contact length, length x speed, then the cutting terms of the model.
Eigen::MatrixXd frictionDesign(const std::vector<FrictionPoint>& pts, int k, double thickness, CuttingModel cutting,
                               const std::vector<double>& speeds) {
  auto speedIndex = [&](double v) {
    for (std::size_t s = 0; s < speeds.size(); ++s)
      if (std::abs(speeds[s] - v) <= 1e-6 * v) return static_cast<int>(s);
    return 0;
  };
  const int n = static_cast<int>(pts.size());
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(n, k);
  for (int i = 0; i < n; ++i) {
    const auto& q = pts[i];
    bool inside = thickness <= 0 || q.z <= thickness;
    double len = thickness > 0 ? std::min(q.z, thickness) : q.z;
    X(i, 0) = len;
    X(i, 1) = len * q.v;
    if (inside) {
      if (cutting == CuttingModel::PerSpeed) X(i, 2 + speedIndex(q.v)) = 1.0;
      if (cutting == CuttingModel::Constant) X(i, 2) = 1.0;
      if (cutting == CuttingModel::Linear) {
        X(i, 2) = 1.0;
        X(i, 3) = q.v;
      }
    }
  }
  return X;
}

// The cutting force at each speed and its standard error, from the fitted coefficients.
void cuttingPerSpeed(FrictionFit& fit, const Eigen::VectorXd& beta, const Eigen::MatrixXd& cov, CuttingModel cutting) {
  for (std::size_t s = 0; s < fit.speeds.size(); ++s) {
    if (cutting == CuttingModel::PerSpeed) {
      fit.cutting.push_back(beta[2 + s]);
      fit.seCutting.push_back(std::sqrt(cov(2 + s, 2 + s)));
    } else if (cutting == CuttingModel::Constant) {
      fit.cutting.push_back(beta[2]);
      fit.seCutting.push_back(std::sqrt(cov(2, 2)));
    } else {
      double v = fit.speeds[s];
      fit.cutting.push_back(beta[2] + beta[3] * v);
      fit.seCutting.push_back(std::sqrt(std::max(0.0, cov(2, 2) + 2 * v * cov(2, 3) + v * v * cov(3, 3))));
    }
  }
}

}  // namespace

FrictionFit fitFrictionCutting(const std::vector<InsertionLog>& logs, double thickness, CuttingModel cutting) {
  if (logs.empty()) throw Error("friction fit: no insertion logs");
  // Without the block thickness the contact length after the tip exits would be taken
  // as still growing, biasing C_p and b_p without any warning: require it.
  if (!(thickness > 0))
    throw InputError({logs.front().file, 0, 0}, "--thickness", "",
                     "the block thickness along the needle is needed to fit friction from insertion logs "
                     "(the shaft length in contact stops growing once the tip exits)",
                     "a length > 0, e.g. --thickness '55 mm'");
  const std::vector<double> speeds = distinctSpeeds(logs);
  const int nCut = cutting == CuttingModel::PerSpeed ? static_cast<int>(speeds.size())
                   : cutting == CuttingModel::Linear  ? 2
                                                      : 1;
  const int k = 2 + nCut;
  FrictionFit fit;
  const std::vector<FrictionPoint> pts = postPuncturePoints(logs, fit);
  const int n = static_cast<int>(pts.size());
  if (n < k + 1)
    throw InputError({logs.front().file, 0, 0}, "data", std::to_string(n) + " points",
                     "too few points after puncture for " + std::to_string(k) + " friction/cutting parameters",
                     "at least " + std::to_string(k + 1) + " points");
  Eigen::MatrixXd X = frictionDesign(pts, k, thickness, cutting, speeds);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) y[i] = pts[i].f;
  // column scaling for conditioning
  Eigen::VectorXd cs = X.colwise().norm().transpose();
  for (int j = 0; j < k; ++j) if (cs[j] == 0) cs[j] = 1;
  Eigen::MatrixXd Xs = X * cs.cwiseInverse().asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xs);
  if (qr.rank() < k)
    throw InputError({logs.front().file, 0, 0}, "data", "",
                     "the logs do not separate friction, damping and cutting (rank " + std::to_string(qr.rank()) + " < " +
                         std::to_string(k) + ")",
                     "logs at two or more speeds, each with points at several depths");
  Eigen::VectorXd beta = qr.solve(y).cwiseQuotient(cs);
  Eigen::VectorXd res = X * beta - y;
  Eigen::MatrixXd cov = res.squaredNorm() / std::max(1, n - k) * (X.transpose() * X).inverse();
  fit.C = beta[0];
  fit.b = beta[1];
  fit.seC = std::sqrt(cov(0, 0));
  fit.seB = std::sqrt(cov(1, 1));
  fit.n = n;
  fit.rmse = std::sqrt(res.squaredNorm() / n);
  fit.speeds = speeds;
  cuttingPerSpeed(fit, beta, cov, cutting);
  fit.fitted.resize(logs.size());
  for (int i = 0; i < n; ++i) fit.fitted[pts[i].run].push_back((X.row(i) * beta)(0));
  return fit;
}

}  // namespace needlesim::fit
