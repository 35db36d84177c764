// The tables of the needle, insertion, output and layer force sections (problem_sections.hpp),
// and the readings that are no single field: the motion profile, output.units.
#include "needlesim/scenario/problem_sections.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "needlesim/scenario/model_section.hpp"

namespace needlesim::scenario {
namespace {

namespace D = units::dim;
constexpr double kDeg = std::numbers::pi / 180.0;

// Plausibility bounds on sizes: a length above them is a slip of the unit ("55 Mm"), not tissue.
// Tissue samples, phantoms and organs of needle-insertion studies are centimetres to tens of
// centimetres (a human torso is under 0.5 m across), so a block side is at most 1 m. The
// longest clinical needles (spinal, biopsy, brachytherapy) are about 0.3 m long, so a needle is at
// most 1 m long; the thickest gauge of the table is 10 G (3.4 mm) and trocars reach about 10 mm,
// so an outer diameter is at most 20 mm.
constexpr double kMaxBlockSide = 1.0;
constexpr double kMaxNeedleLength = 1.0;
constexpr double kMaxNeedleDiameter = 0.02;

ParamTable<TissueSpec> makeBlock() {
  using T = TissueSpec;
  ParamTable<T> t("block");
  t.required(&T::length, "length", D::Length, openClosed(0.0, kMaxBlockSide),
             "extent along the insertion axis (entry face to exit face)")
      .required(&T::width, "width", D::Length, openClosed(0.0, kMaxBlockSide),
                "extent across the insertion axis, in the insertion plane")
      .required(&T::height, "height", D::Length, openClosed(0.0, kMaxBlockSide), "extent out of the insertion plane");
  return t;
}

ParamTable<NeedleSpec> makeNeedle() {
  using N = NeedleSpec;
  ParamTable<N> t("needle");
  t.lengthOrGauge(&N::outer_diameter, &N::inner_diameter, "outer_diameter", openClosed(0.0, kMaxNeedleDiameter),
                  "outer diameter, or a gauge such as 18 G")
      .derived(&N::inner_diameter, "inner_diameter", D::Length, nonNegative(), "from the gauge, else 0 mm",
               [](const N& n, const Scenario&) { return n.inner_diameter; }, "bore diameter (0 = solid)")
      .check([](Section& s, N& n, const Scenario&) {
        if (n.inner_diameter >= n.outer_diameter)
          throw s.error("inner_diameter", fmt::format("{:g} mm", n.inner_diameter * 1e3),
                        "must be smaller than the outer diameter", fmt::format("< {:g} mm", n.outer_diameter * 1e3));
      })
      .required(&N::length, "length", D::Length, openClosed(0.0, kMaxNeedleLength), "free length from the base to the tip")
      .quantity(&N::bevel_angle, "bevel_angle", D::Angle, "deg", openClosed(0.0, 90.0 * kDeg),
                "tip angle alpha of the bevel or cone")
      .choice(&N::tip, "tip", {{"bevel", TipType::Bevel}, {"conical", TipType::Conical}, {"blunt", TipType::Blunt}},
              "tip type")
      .quantity(&N::youngs_modulus, "youngs_modulus", D::Pressure, "GPa", positive(),
                "needle material (stainless steel; Nitinol is 50 GPa in seed 002)")
      .number(&N::poisson, "poisson", Range{-1.0, 0.5, true, true}, "needle Poisson ratio")
      .quantity(&N::density, "density", D::Density, "kg/m^3", positive(), "needle density");
  return t;
}

// An insert or retract segment: its end depth against where the tip is and the needle's length.
void checkDepths(Section& body, const MotionSegment& m, double depth, double needleLength) {
  if (m.kind == MotionSegment::Kind::Retract) {
    if (m.to_depth >= depth)
      throw body.error("to", fmt::format("{:g} mm", m.to_depth * 1e3),
                       fmt::format("a retract must end shallower than where the tip is ({:g} mm)", depth * 1e3),
                       fmt::format("< {:g} mm", depth * 1e3));
    return;
  }
  if (m.to_depth <= depth)
    throw body.error("to", fmt::format("{:g} mm", m.to_depth * 1e3),
                     fmt::format("an insert must go deeper than where the tip is ({:g} mm)", depth * 1e3),
                     fmt::format("> {:g} mm (use retract to go back)", depth * 1e3));
  if (m.to_depth > needleLength)
    throw body.error("to", fmt::format("{:g} mm", m.to_depth * 1e3), "is deeper than the needle is long",
                     fmt::format("<= needle.length = {:g} mm", needleLength * 1e3));
}

// insertion.profile: each segment one of insert / pause / retract / rotate.
void readProfile(Section& s, InsertionSpec& I, const Scenario& sc) {
  auto segs = s.list("profile");
  double depth = I.start_depth;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    if (!segs[i].IsMap() || segs[i].size() != 1)
      throw s.errorAt(segs[i], fmt::format("insertion.profile[{}]", i), segs[i].IsScalar() ? segs[i].Scalar() : "",
                      "each segment must be exactly one of insert / pause / retract / rotate",
                      "e.g. '- insert: {to: 60 mm, speed: 3 mm/s}'");
    Section seg = s.element(segs[i], "profile", i);
    const std::string kind = segs[i].begin()->first.as<std::string>();
    Section body = seg.sub(kind);
    MotionSegment m;
    m.kind = kind == "insert"    ? MotionSegment::Kind::Insert
             : kind == "retract" ? MotionSegment::Kind::Retract
             : kind == "pause"   ? MotionSegment::Kind::Pause
                                 : MotionSegment::Kind::Rotate;
    segmentKindTable(kind).read(body, m, sc);
    if (kind == "insert" || kind == "retract") {
      checkDepths(body, m, depth, sc.needle.length);
      depth = m.to_depth;
    } else if (kind == "rotate") {
      if (m.angle == 0.0) throw body.error("by", "0", "a rotation must turn by a non-zero angle", "!= 0 deg");
      m.duration = std::abs(m.angle) / m.rate;
    }
    I.segments.push_back(m);
  }
}

FieldDoc profileDoc(const ParamTable<InsertionSpec>& t) {
  FieldDoc f = t.otherDoc("profile", Kind::List, "", "motion segments, each one of insert / pause / retract / rotate",
                          "segment");
  f.required = true;
  return f;
}

ParamTable<InsertionSpec> makeInsertion() {
  using I = InsertionSpec;
  ParamTable<I> t("insertion");
  t.quantity(&I::entry_angle, "entry_angle", D::Angle, "deg", openClosed(0.0, 90.0 * kDeg),
             "angle between needle and entry face (90 deg = perpendicular)")
      .quantity(&I::entry_offset, "entry_offset", D::Length, "mm", anyValue(),
                "entry point from the centre of the entry face, in the insertion plane; inside the face (|offset| < "
                "block.width / 2)")
      .quantity(&I::start_depth, "start_depth", D::Length, "mm", anyValue(),
                "tip position along the needle axis at t = 0 (negative = outside)")
      .quantity(&I::bevel_orientation, "bevel_orientation", D::Angle, "deg", anyValue(),
                "initial axial orientation of the bevel")
      .check([](Section& s, I& ins, const Scenario& sc) {
        if (ins.start_depth > sc.needle.length)
          throw s.error("start_depth", "", "is deeper than the needle is long",
                        fmt::format("<= {:g} mm", sc.needle.length * 1e3));
      })
      .row(profileDoc(t), readProfile);
  return t;
}

ParamTable<MotionSegment> makeSegment() {
  ParamTable<MotionSegment> t("segment");
  t.row(t.otherDoc("insert", Kind::Section, "", "advance the tip", "insert"))
      .row(t.otherDoc("pause", Kind::Section, "", "hold still", "pause"))
      .row(t.otherDoc("retract", Kind::Section, "", "withdraw the tip", "retract"))
      .row(t.otherDoc("rotate", Kind::Section, "", "rotate the needle at the current depth", "rotate"));
  return t;
}

ParamTable<MotionSegment> makeSegmentKind(const std::string& kind) {
  using M = MotionSegment;
  ParamTable<M> t(kind);
  if (kind == "insert")
    t.required(&M::to_depth, "to", D::Length, anyValue(), "tip depth at the end of the segment (deeper than at its start)")
        .required(&M::speed, "speed", D::Velocity, positive(), "insertion speed")
        .quantity(&M::rate, "spin_rate", D::AngularVelocity, "deg/s", nonNegative(),
                  "axial spin rate while inserting (duty-cycled steering)")
        .number(&M::duty_cycle, "duty_cycle", closed(0.0, 1.0), "fraction of each cycle spent spinning");
  if (kind == "retract")
    t.required(&M::to_depth, "to", D::Length, anyValue(),
               "tip depth at the end of the segment (shallower than at its start)")
        .required(&M::speed, "speed", D::Velocity, positive(), "retraction speed");
  if (kind == "pause") t.required(&M::duration, "duration", D::Time, positive(), "how long to hold still");
  if (kind == "rotate")
    t.required(&M::angle, "by", D::Angle, anyValue(), "rotation angle (non-zero)")
        .required(&M::rate, "rate", D::AngularVelocity, positive(), "rotation rate")
        .choice(&M::axial, "axis", {{"axial", true}, {"in-plane", false}},
                "about the needle axis (bevel flip) or the base in the insertion plane");
  return t;
}

ParamTable<ModelSpec> makeModel() {
  ParamTable<ModelSpec> t("model");
  std::string help = "engine:";
  std::vector<std::string> names;
  for (const auto& [name, summary] : engineNames()) {
    help += fmt::format("{} {}: {}", names.empty() ? "" : ";", name, summary);
    names.push_back(name);
  }
  t.word(&ModelSpec::engine, "engine", names, help)
      .quantity(&ModelSpec::time_step, "time_step", D::Time, "ms", positive(), "integration step");
  return t;
}

// Per display dimension, the unit the problem (tissue, needle, insertion) writes most often,
// the first written on a tie; the solver's settings (model, output) decide only a dimension
// the problem does not write (a time step in ms does not make durations ms).
units::DisplayUnits mostWrittenUnits(const std::vector<UnitWritten>& written) {
  units::DisplayUnits display;
  for (const auto& d : units::displayDimensions()) {
    const UnitWritten* best = nullptr;
    const auto votes = [](const UnitWritten& w) { return std::pair{w.problem, w.settings}; };
    for (const auto& w : written)
      if (units::displayDimensionOfUnit(w.unit) == &d && (!best || votes(w) > votes(*best))) best = &w;
    if (best) display.prefer(d.name, best->unit);
  }
  return display;
}

// One unit of output.units: InputError at its line for a unit of another dimension or an unknown one.
std::string displayUnitGiven(Section& us, const units::DisplayDimension& d) {
  const YAML::Node n = us.raw(std::string(d.name));
  const std::string key(d.name), text = n.IsScalar() ? n.Scalar() : std::string("a list or section");
  const std::string allowed = fmt::format("one of: {}", fmt::join(d.units, ", "));
  for (const auto u : d.units)
    if (n.IsScalar() && u == text) return us.choice(key);
  if (const units::DisplayDimension* other = units::displayDimensionOfUnit(text))
    throw us.error(key, text, fmt::format("is a unit of {}, not of {}", other->name, d.name), allowed);
  try {
    const units::Quantity q = units::parse("1 " + text);
    if (!(q.dim == d.dim))
      throw us.error(key, text, fmt::format("is a unit of {}, not of {} ({})", units::siName(q.dim), d.name, d.si),
                     allowed);
  } catch (const std::invalid_argument&) {
    throw us.error(key, text, "is not a known unit", allowed);
  }
  throw us.error(key, text, fmt::format("is not one of the units results of {} are shown in", d.name), allowed);
}

// output.units over the units written most often, else SI. Every dimension's unit is
// recorded, so that a summary.json (whose quantities are all SI) shows its results in the
// same units again.
void readDisplayUnits(Section& out, OutputSpec& o, const Scenario&) {
  Section us = out.sub("units");
  const units::DisplayUnits written = mostWrittenUnits(us.unitsWritten());
  units::DisplayUnits display;
  for (const auto& d : units::displayDimensions()) {
    const std::string key(d.name);
    if (us.has(key))
      display.set(d.name, displayUnitGiven(us, d));
    else
      display.prefer(d.name, written.unitFor(d.si));
    us.remember(key, display.unitFor(d.si));
  }
  o.units = display;
}

ParamTable<units::DisplayUnits> makeUnits() {
  ParamTable<units::DisplayUnits> t("units");
  for (const auto& d : units::displayDimensions()) {
    std::string words(d.name);
    std::replace(words.begin(), words.end(), '_', ' ');
    FieldDoc f = t.otherDoc(std::string(d.name), Kind::Choice, "",
                            fmt::format("unit of {} results (SI: {}) on the terminal and in report.html", words, d.si));
    f.choices.assign(d.units.begin(), d.units.end());
    t.row(std::move(f));  // read by readDisplayUnits
  }
  return t;
}

ParamTable<OutputSpec> makeOutput() {
  using O = OutputSpec;
  ParamTable<O> t("output");
  t.text(&O::directory, "directory", "results/<name>", "results folder; an existing one is never overwritten")
      .quantity(&O::interval, "interval", D::Time, "s", nonNegative(),
                "sampling interval of the time series (0 = every step)")
      .quantity(&O::checkpoint_interval, "checkpoint_interval", D::Time, "min", nonNegative(),
                "wall-clock time between checkpoints of a long run, written beside the results folder for "
                "`needlesim run --resume` (0 = none; mpm only so far)")
      .number(&O::max_steps, "max_steps", closed(1.0, 1e15),
              "refuse a run whose step estimate (printed before the first step, and by `needlesim check`) is "
              "larger; raise it to allow a long run")
      .flag(&O::csv, "csv", "write CSV time series")
      .flag(&O::html, "html", "write report.html")
      .row(t.otherDoc("units", Kind::Section, "",
                      "units the terminal and report.html show results in, per dimension (files keep SI); a "
                      "dimension not given here is shown in the unit the file writes most often for it (tissue, "
                      "needle and insertion first, then model and output), else in SI, or in the unit that shows "
                      "the value (an axis or column: its largest) between 0.1 and 1000 when that one does not (20 s, "
                      "not 20000 ms)",
                      "units"),
           readDisplayUnits)
      .check([](Section& s, O& o, const Scenario& sc) {
        if (o.interval > 0.0 && o.interval < sc.model.time_step)
          throw s.error("interval", fmt::format("{:g} s", o.interval), "is shorter than model.time_step",
                        fmt::format(">= {:g} s, or 0 for every step", sc.model.time_step));
      });
  return t;
}

// A default that is another field or a formula, recorded as the value it gives.
double givenOrDerived(Section& s, const std::string& key, double value) {
  if (auto given = s.optNumber(key)) return *given;
  s.rememberNumber(key, value);
  return value;
}

ParamTable<FrictionSpec> makeFriction() {
  using F = FrictionSpec;
  ParamTable<F> t("friction");
  const auto sameAs = [](double F::*of) { return [of](const F& f, const Scenario&) { return f.*of; }; };
  t.quantity(&F::C_p, "C_p", D::ForcePerLength, "N/m", nonNegative(),
             "Karnopp law: dynamic friction per length in contact, insertion (seed 003 eqs 3.23, 5.1)")
      .quantity(&F::b_p, "b_p", D::ForceTimePerArea, "N s/m^2", nonNegative(),
                "Karnopp law: viscous friction per length in contact, insertion")
      .derived(&F::C_n, "C_n", D::ForcePerLength, nonNegative(), "C_p", sameAs(&F::C_p),
               "Karnopp law: dynamic friction per length, retraction")
      .derived(&F::b_n, "b_n", D::ForceTimePerArea, nonNegative(), "b_p", sameAs(&F::b_p),
               "Karnopp law: viscous friction per length, retraction")
      .row(numberDoc("friction", "D_p", D::ForcePerLength, nonNegative(), "C_p + b_p static_band/2",
                     "Karnopp law: static friction limit per length, positive direction"))
      .row(numberDoc("friction", "D_n", D::ForcePerLength, nonNegative(), "C_n + b_n static_band/2",
                     "Karnopp law: static friction limit per length, negative direction (magnitude)"))
      // The struct keeps a zero band for friction built in code; a scenario's band defaults to 0.1 mm/s.
      .row(numberDoc("friction", "static_band", D::Velocity, positive(), "0.1 mm/s",
                     "Karnopp law: band Delta v, |v| < Delta v/2 sticks"),
           [](Section& s, F& f, const Scenario&) { f.static_band = s.number("static_band"); })
      // seed 003 eq 3.23: continuity of the Karnopp law at |v| = Delta v / 2 by default (D_p, D_n above).
      .check([](Section& s, F& f, const Scenario&) {
        f.D_p = givenOrDerived(s, "D_p", f.C_p + f.b_p * f.static_band / 2.0);
        f.D_n = givenOrDerived(s, "D_n", f.C_n + f.b_n * f.static_band / 2.0);
      })
      .number(&F::coefficient, "coefficient", nonNegative(), "Coulomb law: tangential force at most coefficient x normal force (seed 001: 0.3)");
  return t;
}

ParamTable<LayerSpec> makePuncture() {
  using L = LayerSpec;
  ParamTable<L> t("puncture");
  t.optional(&L::puncture_force, "force", D::Force, positive(),
             "force at which the tip punctures the layer (give force or depth)")
      // The engine's stiffness law gives the force at this depth.
      .optional(&L::puncture_depth, "depth", D::Length, positive(),
                "indentation at which the tip punctures the layer (give force or depth)")
      .check([](Section& s, L&, const Scenario&) {
        if (s.has("force") && s.has("depth"))
          throw s.error("depth", "", "give the puncture force or depth, not both", "force or depth");
      });
  return t;
}

ParamTable<LayerSpec> makeCutting() {
  ParamTable<LayerSpec> t("cutting");
  t.quantity(&LayerSpec::cutting_force, "force", D::Force, "N", nonNegative(),
             "constant cutting force while the tip advances inside the layer (seed 003 eq 3.24)");
  return t;
}

ParamTable<LayerSpec> makeInteraction() {
  using L = LayerSpec;
  ParamTable<L> t("interaction");
  t.optional(&L::interaction_stiffness, "K_T", D::Pressure, positive(),
             "needle-tissue interaction stiffness per unit length (seed 002 eq 13)")
      .optional(&L::toughness, "toughness", D::ForcePerLength, positive(),
                "rupture toughness G_c (seed 002 eq 19, seed 004 Table I)");
  return t;
}

}  // namespace

const ParamTable<TissueSpec>& blockTable() {
  static const auto t = makeBlock();
  return t;
}
const ParamTable<NeedleSpec>& needleTable() {
  static const auto t = makeNeedle();
  return t;
}
const ParamTable<InsertionSpec>& insertionTable() {
  static const auto t = makeInsertion();
  return t;
}
const ParamTable<MotionSegment>& segmentTable() {
  static const auto t = makeSegment();
  return t;
}
const ParamTable<MotionSegment>& segmentKindTable(const std::string& kind) {
  static const auto insert = makeSegmentKind("insert"), pause = makeSegmentKind("pause"),
                    retract = makeSegmentKind("retract"), rotate = makeSegmentKind("rotate");
  return kind == "insert" ? insert : kind == "pause" ? pause : kind == "retract" ? retract : rotate;
}
const ParamTable<ModelSpec>& modelTable() {
  static const auto t = makeModel();
  return t;
}
const ParamTable<OutputSpec>& outputTable() {
  static const auto t = makeOutput();
  return t;
}
const ParamTable<units::DisplayUnits>& unitsTable() {
  static const auto t = makeUnits();
  return t;
}
const ParamTable<FrictionSpec>& frictionTable() {
  static const auto t = makeFriction();
  return t;
}
const ParamTable<LayerSpec>& punctureTable() {
  static const auto t = makePuncture();
  return t;
}
const ParamTable<LayerSpec>& cuttingTable() {
  static const auto t = makeCutting();
  return t;
}
const ParamTable<LayerSpec>& interactionTable() {
  static const auto t = makeInteraction();
  return t;
}

}  // namespace needlesim::scenario
