#include "needlesim/engines/steering/steering_engines.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/engines/run_cost.hpp"
#include "needlesim/engines/steering/beam_foundation.hpp"
#include "needlesim/engines/steering/curvature_fit.hpp"
#include "needlesim/engines/steering/energy_model.hpp"
#include "needlesim/materials/material_spec.hpp"
#include "needlesim/results/display_units.hpp"

namespace needlesim::engines {
namespace {

using steering::Control;
using steering::Pose;
using steering::Vec3;
constexpr double pi = std::numbers::pi;

InputError inputError(const Scenario& sc, const std::string& field, const std::string& value,
                      const std::string& problem, const std::string& allowed) {
  return InputError(sc.where(field), field, value, problem, allowed);
}

struct Result {
  const char* key;
  double value;
  const char* unit;
  const char* meaning;
};
void report(ResultSink& sink, std::initializer_list<Result> results) {
  for (const Result& r : results) sink.result(r.key, r.value, r.unit, r.meaning);
}

// Cumulative arc length of a polyline.
std::vector<double> arcLengths(const std::vector<Vec3>& p) {
  std::vector<double> s(p.size(), 0.0);
  for (std::size_t i = 1; i < p.size(); ++i) s[i] = s[i - 1] + (p[i] - p[i - 1]).norm();
  return s;
}

struct Shape {
  double inserted = 0.0;  // m
  std::vector<Vec3> nodes;
};

// A point of the model frame in the tissue frame (SteeringInputs::frame).
Vec3 inTissue(const needle::InsertionFrame& f, const Vec3& p) {
  return f.entry + p.z() * f.axial + p.y() * f.lateral - p.x() * f.outOfPlane;
}

// tip_path.csv and needle_shapes.csv in the tissue frame (docs/results.md).
void pathTables(const SteeringInputs& in, const std::vector<Vec3>& path, const std::vector<Shape>& shapes,
                ResultSink& sink) {
  const std::vector<double> s = arcLengths(path);
  io::Table tip({{"insertion", "m"}, {"tip_x", "m"}, {"tip_y", "m"}, {"tip_z", "m"}, {"tip_deflection", "m"},
                 {"bevel_angle", "rad"}});
  tip.reserve(path.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    const Vec3 p = inTissue(in.frame, path[i]);
    tip.addRow({s[i], p.x(), p.y(), p.z(), std::hypot(path[i].x(), path[i].y()), bevelAngleAt(in.plan, s[i])});
  }
  io::Table shp({{"snapshot", "1"}, {"inserted_length", "m"}, {"s", "m"}, {"x", "m"}, {"y", "m"}, {"z", "m"}});
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    const auto ss = arcLengths(shapes[k].nodes);
    for (std::size_t j = 0; j < shapes[k].nodes.size(); ++j) {
      const Vec3 p = inTissue(in.frame, shapes[k].nodes[j]);
      shp.addRow({static_cast<double>(k + 1), shapes[k].inserted, ss[j], p.x(), p.y(), p.z()});
    }
  }
  sink.table("tip_path", std::move(tip));
  sink.table("needle_shapes", std::move(shp));
}

// A length for a note, in the scenario's display unit: "250 mm".
std::string lengthText(const SteeringInputs& in, double metres) {
  return results::shownText(metres, "m", in.display, "{:.4g}");
}

// A stretch of the path for a note, in the display unit of lengths: "0-75 mm".
std::string spanText(const SteeringInputs& in, double s0, double s1) {
  const double largest = std::max(std::abs(s0), std::abs(s1));  // both ends in one unit
  const units::Shown a = units::shown(s0, "m", in.display, largest), b = units::shown(s1, "m", in.display, largest);
  return fmt::format("{:.4g}-{:.4g} {}", a.value, b.value, b.unit);
}

// The arc lengths at which the plan rotates the bevel: where one arc of the path may end.
std::vector<double> bevelRotations(const std::vector<Control>& plan) {
  std::vector<double> at;
  double s = 0.0;
  for (const Control& c : plan) {
    if (c.rotate != 0.0 && s > 0.0) at.push_back(s);
    s += c.length;
  }
  return at;
}

// Final tip position; a coordinate within round-off of the path length (1e-12 of it) is 0.
void tipResults(const SteeringInputs& in, const std::vector<Vec3>& path, double length, ResultSink& sink) {
  const auto clean = [&](double v) { return std::abs(v) <= 1e-12 * length ? 0.0 : v; };
  const Vec3 end = path.back(), tip = inTissue(in.frame, end);
  sink.result("final_deflection", clean(std::hypot(end.x(), end.y())), "m",
              "tip distance from the entry axis at the end of the insertion");
  sink.result("tip_x", clean(tip.x()), "m", "final tip depth from the entry face (tissue frame)");
  sink.result("tip_y", clean(tip.y()), "m", "final tip position across the width, in the insertion plane (bevel 0 steers to -y)");
  sink.result("tip_z", clean(tip.z()), "m", "final tip position out of the insertion plane");
  sink.result("inserted_length", length, "m", "length of the tip path");
}

// The radii of the three 50 mm sections of seed 002 Table 2 that are circular arcs; the
// names of those left out because they are not.
std::vector<std::string> sectionResults(const std::vector<Vec3>& path, double length, ResultSink& sink) {
  const char* names[3] = {"radius_0_50mm", "radius_50_100mm", "radius_100_150mm"};
  std::vector<std::string> notArcs;
  double sum = 0.0;
  int reported = 0;
  for (int k = 0; k < 3; ++k) {
    if (length < (k + 1) * 0.05 - 1e-5) continue;  // chords: 10 um slack
    const auto section = steering::pathSection(path, k * 0.05, (k + 1) * 0.05);
    const steering::CircleFit f = steering::fitCircle(section);
    if (!std::isfinite(f.radius)) continue;  // straight
    if (!steering::isOneArc(f, section)) {
      notArcs.emplace_back(names[k]);
      continue;
    }
    sink.result(names[k], f.radius, "m", fmt::format("radius of curvature fitted over {}-{} mm of the path", 50 * k, 50 * (k + 1)));
    sum += f.radius;
    ++reported;
  }
  if (reported == 3) sink.result("radius_mean", sum / 3, "m", "mean of the three section radii (seed 002 Table 2)");
  return notArcs;
}

// A path that is not one arc: the radius of each piece between bevel rotations that is one,
// and a note saying why there is no radius for the whole path.
void piecewiseArcResults(const SteeringInputs& in, const std::vector<Vec3>& path, const steering::CircleFit& whole,
                         std::vector<std::string> leftOut, ResultSink& sink) {
  const std::vector<double> breaks = bevelRotations(in.plan);
  const std::vector<steering::PathPiece> pieces = steering::pathPieces(path, breaks);
  std::string arcs;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const steering::PathPiece& p = pieces[k];
    const std::string span = spanText(in, p.s0, p.s1);
    const std::string sep = k == 0 ? "" : (k + 1 == pieces.size() ? " and " : ", ");
    if (p.arc) {
      sink.result(fmt::format("radius_arc{}", k + 1), p.fit.radius, "m",
                  fmt::format("radius of curvature of the arc over {} of the path (between bevel rotations)", span));
      arcs += fmt::format("{}an arc of radius {} over {}", sep, lengthText(in, p.fit.radius), span);
    } else {
      arcs += fmt::format("{}{} over {}", sep, p.straight ? "a straight piece" : "a piece that is no arc either", span);
    }
  }
  leftOut.insert(leftOut.begin(), "radius_whole");
  const std::string why =
      fmt::format("a circle fitted to it is {} off the path on average, {:.0f} % of the path's sagitta",
                  lengthText(in, whole.rms), 100 * whole.rms / steering::sagitta(path));
  const std::string shape =
      pieces.size() > 1
          ? fmt::format("The tip path is not one circular arc ({}): between bevel rotations it is {}.", why, arcs)
          : fmt::format("The tip path is not one circular arc ({}), and no bevel rotation splits it into arcs.", why);
  sink.note(shape + fmt::format(" A radius fitted across them describes no part of the path: {} {} not reported.",
                                fmt::join(leftOut, ", "), leftOut.size() == 1 ? "is" : "are"));
}

// Final tip and the radii of curvature (seed 002 section 5.1, Table 2): over the three 50 mm
// sections and the whole path when each is one circular arc; for a path that is not (an
// S-curve after a bevel flip), the arcs between bevel rotations. Returns the whole path's
// radius when it is one arc (else infinity: no Pi1).
double pathResults(const SteeringInputs& in, const std::vector<Vec3>& path, ResultSink& sink) {
  const double length = arcLengths(path).back();
  tipResults(in, path, length, sink);
  std::vector<std::string> leftOut = sectionResults(path, length, sink);
  const steering::CircleFit whole = steering::fitCircle(path);
  if (!std::isfinite(whole.radius)) {
    sink.result("curvature_whole", 0.0, "1/m", "curvature of the whole path (0: a straight path)");
    sink.note("The tip path is straight: it has no radius of curvature (radius_whole is not reported).");
    return whole.radius;
  }
  if (steering::isOneArc(whole, path)) {
    sink.result("radius_whole", whole.radius, "m", "radius of curvature fitted over the whole path (rho_exp of Table 2)");
    sink.result("curvature_whole", 1.0 / whole.radius, "1/m", "1 / radius_whole");
    if (!leftOut.empty())
      sink.note(fmt::format("Not every 50 mm section is a circular arc: {} not reported.", fmt::join(leftOut, ", ")));
    return whole.radius;
  }
  if (!leftOut.empty()) leftOut.emplace_back("radius_mean");
  piecewiseArcResults(in, path, whole, std::move(leftOut), sink);
  return std::numeric_limits<double>::infinity();
}

// Seed 002's groups (eqs 1-3) and, when its length scale is within 1e3 of the inserted length,
// seed 004's (eqs 2-3); otherwise a note with their values says why they are left out.
void groupResults(const SteeringInputs& in, double length, double rho, ResultSink& sink) {
  needle::DimensionalInput d{in.section.youngs_modulus, in.section.secondMoment(), in.alpha, in.C10, in.Gc,
                             in.mu, in.P_input, length, std::isfinite(rho) ? rho : 0.0};
  const needle::DimensionalGroups g = needle::dimensionalGroups(d);
  if (std::isfinite(rho)) sink.result("Pi1", g.Pi1, "1", "rho/rho0, seed 002 eq 2");
  report(sink, {{"rho0", g.rho0, "m", "length scale Gc^2/(E C10 I^1/4), seed 002 eq 3"},
                {"Pi2", g.Pi2, "1", "P_input E C10 I^1/4 / Gc^3, seed 002 eq 2"},
                {"Pi3", g.Pi3, "1", "alpha E C10 I^1/2 / Gc^2, seed 002 eq 2"}});
  sink.result("Pi4", g.Pi4, "1",
              in.mu == 0 ? "mu E C10 I^1/2 / Gc^2, seed 002 eq 2 (0: no friction, mu = 0)"
                         : "mu E C10 I^1/2 / Gc^2, seed 002 eq 2");
  const double scale = g.s004_length / length;
  if (scale >= 1e-3 && scale <= 1e3) {
    report(sink, {{"length_s004", g.s004_length, "m", "E Gc / C10^2, seed 004 eq 3"},
                  {"Pi2_s004", g.s004_Pi2, "1", "I C10^5 / (E Gc^4), seed 004 eq 2"},
                  {"Pi3_s004", g.s004_Pi3, "1", "u C10^2 / (E Gc), u = inserted length, seed 004 eq 2"}});
    return;
  }
  sink.note(fmt::format("Seed 004's length scale E Gc / C10^2 (eq 3) is {} here, {:.2g} times the inserted length, so "
                        "its groups I C10^5 / (E Gc^4) = {:.2g} and u C10^2 / (E Gc) = {:.2g} (eq 2) say only that this "
                        "needle is far from that scale; they are not reported as key results.",
                        lengthText(in, g.s004_length), scale, g.s004_Pi2, g.s004_Pi3));
}

// Tip loads (seed 002 eqs 24-26), the roller reaction of section 4 and the dimensional
// analysis (seed 002 eqs 1-3, seed 004 eqs 1-3); rho: the whole path's radius (inf: none).
void loadResults(const SteeringInputs& in, double length, double rho, ResultSink& sink) {
  sink.result("tip_P", in.tip.P, "N", "axial tip load, seed 002 eq 24");
  sink.result("tip_Q", in.tip.Q, "N", "transverse tip load from the bevel edges, seed 002 eq 25 (- = towards the sharp side)");
  sink.result("tip_M", in.tip.M, "N m", "tip moment, seed 002 eq 26");
  sink.result("roller_Q", in.roller_Q, "N", "transverse roller reaction -P_input/tan(beta) (seed 002 section 4, sub-step 1)");
  sink.result("K_T", in.K_T, "N/m^2", in.K_T_from_material ? "interaction stiffness, 1.5 C10 (eq 13 with d/h = 1)"
                                                          : "interaction stiffness (tissue interaction.K_T)");
  sink.result("EI", in.section.EI(), "N m^2", "needle flexural rigidity");
  sink.result("beta", in.beta, "rad", "cut angle beta = beta_over_alpha * bevel angle");
  if (!(in.Gc > 0 && in.C10 > 0)) {
    sink.note("No rupture toughness given (tissue interaction.toughness): the Pi groups and rho_0 of seed 002 "
              "eqs 1-3 are not reported.");
    return;
  }
  groupResults(in, length, rho, sink);
}

// Plots in mm, tissue frame: the tip path (depth x against y and z), the deflection from
// the entry axis, and the needle shapes.
void pathPlots(const SteeringInputs& in, const std::string& engine, const std::vector<Vec3>& path,
               const std::vector<Shape>& shapes, ResultSink& sink) {
  std::vector<double> xmm, ymm, zmm, lat;
  bool outOfPlane = false;
  for (const Vec3& q : path) {
    const Vec3 p = inTissue(in.frame, q);
    xmm.push_back(p.x() * 1e3);
    ymm.push_back(p.y() * 1e3);
    zmm.push_back(p.z() * 1e3);
    lat.push_back(std::hypot(q.x(), q.y()) * 1e3);
    outOfPlane = outOfPlane || std::abs(q.x()) > 1e-9;
  }
  io::Plot pathPlot{"Tip path (" + engine + ")", "depth x [mm]", "tip position [mm]", {}};
  pathPlot.series.push_back({"y (insertion plane)", xmm, ymm, false, false});
  if (outOfPlane) pathPlot.series.push_back({"z (out of plane)", xmm, zmm, false, true});
  sink.plot(std::move(pathPlot));
  sink.plot(io::Plot{"Deflection against depth", "depth x [mm]", "distance from the entry axis [mm]",
                     {{"lateral deflection", xmm, lat, false, false}}});
  if (shapes.empty()) return;
  io::Plot sp{"Needle shapes along the insertion", "depth x [mm]", "y [mm]", {}};
  for (const Shape& sh : shapes) {
    io::PlotSeries ser{fmt::format("{:.0f} mm inserted", sh.inserted * 1e3), {}, {}, false, false};
    for (const Vec3& q : sh.nodes) {
      const Vec3 p = inTissue(in.frame, q);
      ser.x.push_back(p.x() * 1e3);
      ser.y.push_back(p.y() * 1e3);
    }
    sp.series.push_back(std::move(ser));
  }
  sink.plot(std::move(sp));
}

// Common report of the three steering engines.
void report(const SteeringInputs& in, const std::string& engine, const std::vector<Vec3>& path,
            const std::vector<Shape>& shapes, ResultSink& sink) {
  const double rho = pathResults(in, path, sink);
  loadResults(in, arcLengths(path).back(), rho, sink);
  pathPlots(in, engine, path, shapes, sink);
  for (const auto& n : in.notes) sink.note(n);
  pathTables(in, path, shapes, sink);
}

// Inserted lengths at which the needle shape is recorded.
std::vector<double> snapshotLengths(const SteeringInputs& in, int n) {
  std::vector<double> l;
  for (int k = 1; k <= n; ++k) l.push_back(in.insertion * k / n);
  return l;
}

}  // namespace

double bevelAngleAt(const std::vector<Control>& plan, double s) {
  double a = 0.0, s0 = 0.0;
  for (const Control& c : plan) {
    if (s < s0 || (s == s0 && s0 > 0)) break;
    a += c.rotate;
    const double local = std::min(s - s0, c.length);
    if (c.duty_cycle > 0) {
      const int cycles = std::max(1, static_cast<int>(std::lround(c.length / c.cycle_length)));
      const double lc = c.length / cycles, ls = c.duty_cycle * lc;
      const double k = std::min(std::floor(local / lc), static_cast<double>(cycles));
      const double t = local - k * lc;
      a += 2 * pi * k + (t < ls ? 2 * pi * t / ls : (k < cycles ? 2 * pi : 0.0));
    } else {
      a += c.spin * local;
    }
    s0 += c.length;
  }
  return a;
}

namespace {

// Tissue properties of the one layer the steering models take (seed 002 eq 13 for K_T).
void tissueInputs(const Scenario& sc, SteeringInputs& in) {
  if (sc.tissue.layers.size() > 1)
    throw inputError(sc, "tissue.layers", fmt::format("{} layers", sc.tissue.layers.size()),
                     "engine " + sc.model.engine + " models one homogeneous tissue (seed 002)",
                     "one layer, or engine realtime2d, explicit or mpm for layered tissue");
  const LayerSpec& L = sc.tissue.layers.front();
  const auto mod = materials::smallStrainModuli(L.material);
  in.C10 = mod.shear / 2;  // neo-Hookean: mu = 2 C10
  in.E_T = mod.youngs();
  in.nu_T = mod.poisson();
  if (L.interaction_stiffness > 0) {
    in.K_T = L.interaction_stiffness;
  } else {
    // seed 002 eq 13, K_T = 1.5 C10 d/h, for a sample as high as wide (the cubes of seed 004)
    in.K_T = 1.5 * in.C10;
    in.K_T_from_material = true;
    in.notes.push_back(fmt::format("K_T not given (tissue interaction.K_T): 1.5 C10 = {:.4g} N/m^2 from the material "
                                   "(seed 002 eq 13 with sample d/h = 1).", in.K_T));
  }
  in.Gc = L.toughness;
  in.mu = L.friction.coefficient;
}

// Tip loads: eqs 24-26 at beta; the section-4 roller reaction -P_input/tan(beta).
void tipLoadInputs(const Scenario& sc, bool bevel, SteeringInputs& in) {
  const SteeringModelSpec& st = sc.model.steering;
  in.P_input = st.input_force;
  in.tip = needle::bevelTipLoads({in.K_T, sc.needle.outer_diameter, in.alpha, in.beta, in.P_input});
  in.roller_Q = in.beta > 0 ? -in.P_input / std::tan(in.beta) : 0.0;
  if (!bevel) {
    in.Q = in.M = 0.0;
    in.P = in.P_input;
  } else if (st.tip_load == "roller") {
    in.Q = in.roller_Q;
    in.M = 0.0;
    in.P = in.P_input;
  } else {
    in.Q = in.tip.Q;
    in.M = in.tip.M;
    in.P = in.tip.P;
  }
  in.kappa_bof = steering::beamFoundationSteadyCurvature(in.section.EI(), in.K_T, in.Q, in.M);
}

// The control of one insert segment: the rotation pending before it, spinning or duty cycling.
Control insertControl(const Scenario& sc, std::size_t i, double length, double& pending) {
  const MotionSegment& m = sc.insertion.segments[i];
  Control c;
  c.rotate = pending;
  pending = 0.0;
  c.length = length;
  if (m.duty_cycle > 0) {
    if (!(m.rate > 0))
      throw inputError(sc, fmt::format("insertion.profile[{}].insert.spin_rate", i), "0",
                       "duty cycling needs a spin rate", "> 0 deg/s");
    // one full turn per cycle at spin_rate during duty_cycle of the cycle's time
    c.duty_cycle = m.duty_cycle;
    c.cycle_length = m.speed * 2 * pi / (m.rate * m.duty_cycle);
  } else {
    c.spin = m.rate / m.speed;  // rad per metre of insertion
  }
  return c;
}

// Insertion plan per inserted length inside the tissue. Rotations act before the next
// insertion; a retraction followed by re-insertion follows the channel already cut.
void planInputs(const Scenario& sc, SteeringInputs& in) {
  in.start = std::max(0.0, sc.insertion.start_depth);
  double depth = sc.insertion.start_depth, deepest = in.start, pending = sc.insertion.bevel_orientation;
  bool retracted = false;
  for (std::size_t i = 0; i < sc.insertion.segments.size(); ++i) {
    const MotionSegment& m = sc.insertion.segments[i];
    if (m.kind == MotionSegment::Kind::Rotate) {
      if (!m.axial)
        throw inputError(sc, fmt::format("insertion.profile[{}].rotate.axis", i), "in-plane",
                         "is not supported by the steering engines (the base is held by the support sheath)", "axial");
      pending += m.angle;
    } else if (m.kind == MotionSegment::Kind::Retract) {
      retracted = true;
      depth = m.to_depth;
    } else if (m.kind == MotionSegment::Kind::Insert) {
      const double from = std::max(depth, deepest);
      depth = m.to_depth;
      if (m.to_depth <= from) continue;
      in.plan.push_back(insertControl(sc, i, m.to_depth - from, pending));
      deepest = m.to_depth;
    }
  }
  if (retracted)
    in.notes.push_back("Retractions: the needle withdraws along its own channel; re-insertion cuts new tissue only "
                       "beyond the deepest point reached.");
  if (sc.insertion.start_depth > 0)
    in.notes.push_back("The tip starts inside the tissue: the first start_depth of the path is taken as straight.");
  in.insertion = deepest - in.start;
}

}  // namespace

SteeringInputs steeringInputs(const Scenario& sc) {
  SteeringInputs in;
  const NeedleSpec& nd = sc.needle;
  const SteeringModelSpec& st = sc.model.steering;
  in.section = needle::Section{nd.youngs_modulus, nd.outer_diameter, nd.inner_diameter};
  in.alpha = nd.bevel_angle;
  if (!(in.alpha < pi / 2))
    throw inputError(sc, "needle.bevel_angle", "90 deg", "leaves no bevel for the steering engines", "< 90 deg");
  const bool bevel = nd.tip == TipType::Bevel;
  in.beta = bevel ? st.beta_over_alpha * in.alpha : 0.0;
  if (!bevel) in.notes.push_back("Symmetric (conical or blunt) tip: no tip asymmetry, so the needle goes straight.");
  in.frame = needle::InsertionFrame::fromInsertion(sc.insertion);
  in.display = sc.output.units;
  tissueInputs(sc, in);
  tipLoadInputs(sc, bevel, in);
  planInputs(sc, in);
  if (!(in.insertion > 0))
    throw inputError(sc, "insertion.profile", "", "never inserts the tip into the tissue", "an insert to a depth > 0");
  if (!(st.increment < in.insertion))
    throw inputError(sc, "model.steering.increment", fmt::format("{:g} mm", st.increment * 1e3),
                     "is not shorter than the insertion", fmt::format("< {:g} mm", in.insertion * 1e3));
  return in;
}

StepPlan steeringStepPlan(const Scenario& sc) {
  const SteeringInputs in = steeringInputs(sc);
  StepPlan p;
  p.engine = sc.model.engine;
  p.fewerSteps = "a larger model.steering.increment";
  p.secondsPerStep = run_cost::kSteeringStep;
  for (const Control& c : in.plan)
    p.steps += std::ceil(c.length / sc.model.steering.increment) + (c.duty_cycle > 0 ? 2.0 * c.length / c.cycle_length : 0.0);
  return p;
}

// ---------------------------------------------------------------- kinematic
void runKinematic(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  SteeringInputs in = steeringInputs(sc);
  guardAndAnnounce(sc, steeringStepPlan(sc), sink, options);
  const SteeringModelSpec& st = sc.model.steering;
  // Webster et al. 2006: constant curvature towards the bevel (-y of the tip frame).
  // Without a given curvature: the beam-on-foundation steady curvature of the tip loads.
  const double kappa = st.curvature >= 0 ? st.curvature : -in.kappa_bof;
  if (st.curvature < 0)
    in.notes.push_back(fmt::format("Curvature not given: {:.4g} 1/m from the tip loads, (M + Q/lambda)/EI of the "
                                   "beam on a foundation (docs/models/steering.md).", kappa));
  steering::KinematicParams par{kappa, st.increment};
  Pose start;
  start.p = Vec3(0, 0, in.start);
  std::vector<Vec3> path(steering::kinematicSampleCount(par, in.plan));
  const int n = steering::simulateKinematic(par, start, in.plan, path);
  path.resize(n);
  if (in.start > 0) path.insert(path.begin(), Vec3::Zero());
  // the needle follows its tip: the shape at inserted length L is the path up to L
  std::vector<Shape> shapes;
  const auto s = arcLengths(path);
  for (double L : snapshotLengths(in, st.snapshots)) {
    Shape sh{L, {}};
    for (std::size_t i = 0; i < path.size() && s[i] <= in.start + L + 1e-9; ++i) sh.nodes.push_back(path[i]);
    shapes.push_back(std::move(sh));
  }
  sink.result("curvature", kappa, "1/m", "kinematic curvature with the bevel fixed");
  if (kappa != 0) sink.result("radius_model", 1 / std::abs(kappa), "m", "1 / curvature");
  sink.note("Kinematic bevel-tip model (Webster et al. 2006) in 3D: constant curvature towards the bevel, exact "
            "SE(3) integration, axial rotations, spinning and duty cycling (docs/models/steering.md).");
  report(in, "kinematic", path, shapes, sink);
}

// ---------------------------------------------------------------- beam on foundation
void runBeamFoundation(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  SteeringInputs in = steeringInputs(sc);
  guardAndAnnounce(sc, steeringStepPlan(sc), sink, options);
  const SteeringModelSpec& st = sc.model.steering;
  const int n = static_cast<int>(std::ceil(in.insertion / st.increment - 1e-9));
  const double h = in.insertion / n;
  steering::BeamFoundationParams p{in.section.EI(), in.K_T, in.Q, in.M, -in.P, h, in.insertion + 3 * h};
  steering::BeamFoundationModel model(p);
  Pose entry;
  entry.p = Vec3(0, 0, in.start);
  model.reset(entry, 0.0);
  const auto snaps = snapshotLengths(in, st.snapshots);
  std::vector<Shape> shapes;
  std::size_t next = 0;
  double bevel = 0.0;
  Progress progress("beam-foundation", options.progress);
  for (int i = 0; i < n; ++i) {
    const double target = bevelAngleAt(in.plan, (i + 0.5) * h);  // bevel during this increment
    model.rotateBevel(target - bevel);
    bevel = target;
    model.advance();
    const double L = (i + 1) * h;
    while (next < snaps.size() && L >= snaps[next] - 1e-9) {
      Shape sh{L, {}};
      model.shape(sh.nodes);
      shapes.push_back(std::move(sh));
      ++next;
    }
    if ((i & 255) == 0) progress.update(static_cast<double>(i) / n);
  }
  progress.finish();
  std::vector<Vec3> path(model.path().begin(), model.path().end());
  if (in.start > 0) path.insert(path.begin(), Vec3::Zero());
  sink.result("applied_Q", in.Q, "N", "transverse tip load applied (model.steering.tip_load)");
  sink.result("applied_M", in.M, "N m", "tip moment applied");
  sink.result("curvature_closed_form", -in.kappa_bof, "1/m",
              "steady curvature towards the bevel, -(M + Q/lambda)/EI (h -> 0 limit, docs/models/steering.md)");
  sink.result("increments", n, "1", "insertion increments (= beam elements)");
  sink.note(fmt::format("Beam on an elastic foundation: Euler-Bernoulli needle, foundation K_T only along the cut "
                        "channel, tip loads from '{}' (docs/models/steering.md).", st.tip_load));
  report(in, "beam-foundation", path, shapes, sink);
}

// ---------------------------------------------------------------- energy (seed 002 section 4)
// The energy model's parameters (seed 002 section 4); refuses what the planar model cannot do.
steering::EnergyParams energyParams(const Scenario& sc, const SteeringInputs& in) {
  const SteeringModelSpec& st = sc.model.steering;
  steering::EnergyParams p;
  p.E = in.section.youngs_modulus;
  p.diameter = in.section.outer_diameter;
  p.inner_diameter = in.section.inner_diameter;
  p.alpha = in.alpha;
  p.beta_ratio = in.alpha > 0 ? in.beta / in.alpha : 0.0;
  p.K_T = in.K_T;
  p.P_input = in.P_input;
  p.friction_fraction = st.friction_dissipation;
  p.Gc = in.Gc;
  p.tear_length = st.tear_length > 0 ? st.tear_length : -1.0;
  p.fracture_energy = st.fracture_energy;
  p.E_T = in.E_T;
  p.nu_T = std::min(in.nu_T, 0.499);
  p.medium_volume = sc.tissue.length * sc.tissue.width * sc.tissue.height;
  p.insertion = in.start + in.insertion;
  p.max_step = st.max_step;
  p.frame = st.energy_frame == "path-window" ? steering::EnergyFrame::PathWindow : steering::EnergyFrame::Entry;
  // 2D: only 180-degree flips (seed 002 section 4 is planar)
  double s0 = in.start;
  for (std::size_t i = 0; i < in.plan.size(); ++i) {
    const Control& c = in.plan[i];
    if (c.spin != 0 || c.duty_cycle > 0)
      throw inputError(sc, "insertion.profile", "spin_rate / duty_cycle",
                       "the energy model is 2D and cannot spin the needle", "kinematic or beam-foundation");
    const double turns = c.rotate / pi;
    if (std::abs(turns - std::round(turns)) > 1e-9)
      throw inputError(sc, "insertion.profile", fmt::format("{:g} deg", c.rotate * 180 / pi),
                       "the energy model is 2D: bevel rotations must be 180-degree flips", "multiples of 180 deg");
    const long k = std::lround(turns);
    if (k % 2 != 0) p.flip_depths.push_back(s0);
    s0 += c.length;
  }
  if (!(p.insertion > p.initial_length))
    throw inputError(sc, "insertion.profile", "", "inserts less than the energy model's initial 1 mm", "> 1 mm");
  return p;
}

StepPlan energyStepPlan(const Scenario& sc) {
  energyParams(sc, steeringInputs(sc));  // the energy model's own refusals, for check as for run
  return steeringStepPlan(sc);
}

void runEnergy(const Scenario& sc, ResultSink& sink, const RunOptions& options) {
  SteeringInputs in = steeringInputs(sc);
  guardAndAnnounce(sc, steeringStepPlan(sc), sink, options);
  const SteeringModelSpec& st = sc.model.steering;
  const steering::EnergyParams p = energyParams(sc, in);
  std::vector<Eigen::Vector3d> raw;
  std::vector<steering::EnergyIncrement> incs;
  Progress progress("energy", options.progress);
  const steering::EnergyResult r = steering::runEnergyModel(p, &raw, st.increment, &incs);
  progress.finish();
  // model frame (x along the axis, v) -> entry frame (z, y = v). The roller of sub-step 1
  // pushes the tip to +v, but the released loads of sub-step 2 carry it past straight, so the
  // net path bends to -v (docs/models/bevel-tip-energy.md, status); y = v makes bevel 0 steer
  // towards -y as in the other engines.
  std::vector<Vec3> path{Vec3::Zero()};
  for (const auto& q : raw) path.emplace_back(0.0, q.y(), q.x());
  const auto snaps = snapshotLengths(in, st.snapshots);
  std::vector<Shape> shapes;
  std::size_t next = 0;
  for (std::size_t i = 0; i < incs.size() && next < snaps.size(); ++i) {
    const double l = incs[i].length;
    const bool last = i + 1 == incs.size();
    if (l - in.start >= snaps[next] - 1e-9 || last) {
      Shape sh{l - in.start, {}};
      const int m = std::max(2, static_cast<int>(std::ceil(l / st.increment)));
      for (int j = 0; j <= m; ++j) {
        const double x = l * j / m;
        sh.nodes.emplace_back(0.0, steering::energyDeflection(incs[i].coeffs, l, x), x);
      }
      shapes.push_back(std::move(sh));
      ++next;
    }
  }
  // increments (thinned to at most ~2000 rows): tip, slope and the sub-step loads
  io::Table it({{"length", "m"}, {"tip_deflection", "m"}, {"phi", "rad"}, {"P", "N"}, {"Q", "N"}, {"H", "N"}, {"V", "N"}});
  const std::size_t every = std::max<std::size_t>(1, incs.size() / 2000);
  for (std::size_t i = 0; i < incs.size(); ++i)
    if (i % every == 0 || i + 1 == incs.size()) {
      const auto& e = incs[i];
      it.addRow({e.length, e.tip_v, e.phi, e.P, e.Q, e.H, e.V});
    }
  report(sink, {{"increments", static_cast<double>(r.increments), "1", "insertion increments (set by P_input, seed 002 Fig 21)"},
                {"W_input", r.W_input, "J", "work of the input force (eq 41, choice 1)"},
                {"W_Q", r.W_Q, "J", "work of the released transverse tip loads (eq 42)"},
                {"W_P", r.W_P, "J", "work of the released axial tip loads (eq 43)"},
                {"W_R", r.W_R, "J", "rupture work a G_f u (eq 44, choices 5, 10)"},
                {"W_friction", r.W_friction, "J", "input work dissipated by friction (Fig 23, choice 7)"},
                {"cut_share", r.cut_share, "1", "share of the push that cuts sideways, 1 - a G_f / P_eff (choice 10)"},
                {"U_B", r.U_B, "J", "bending energy of the increments (eq 35)"},
                {"U_T", r.U_T, "J", "needle-tissue interaction energy (eq 40)"}});
  if (r.U_C > 0) sink.result("U_C", r.U_C, "J", "tissue compression energy at the end (eq 39)");
  if (r.capped)
    sink.warning(fmt::format("Some increments hit max_step ({:g} mm): the roller was (nearly) parallel to the axis.",
                             st.max_step * 1e3));
  sink.note("Energy-based incremental model of seed 002 section 4 (eqs 27-49) with the choices of "
            "docs/models/bevel-tip-energy.md. 2D: only 180-degree bevel flips.");
  sink.table("increments", std::move(it));
  report(in, "energy", path, shapes, sink);
}

}  // namespace needlesim::engines
