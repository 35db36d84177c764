// The end of an mpm run: key results, plots, tables and notes.
#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "needlesim/engines/mpm/marker_errors.hpp"
#include "needlesim/engines/mpm/mpm_run.hpp"
#include "needlesim/results/layer_boundaries.hpp"

namespace needlesim::engines {

namespace {

std::vector<double> millimetres(std::vector<double> v) {
  for (double& x : v) x *= 1e3;
  return v;
}

}  // namespace

void MpmRun::emit(bool stopped) {
  const Summary& s = sum_;
  sink_.result("peak_force", s.peak, "N", "largest axial force on the needle (resisting insertion)");
  if (!stopped) warnZeroForce(sc_, s.peak, sink_);
  sink_.result("peak_force_depth", s.peakDepth, "m", "tip depth at the peak force");
  sink_.result("final_force", s.lastForce, "N", "axial force on the needle at the final depth");
  sink_.result("final_tip_force", s.lastTip, "N", "axial force on the tip faces at the final depth");
  sink_.result("final_shaft_force", s.lastShaft, "N", "axial force on the shaft (friction) at the final depth");
  sink_.result("final_depth", ms_.depth, "m", "tip depth at the end");
  emitEnergy();
  fracture_.results(sink_);
  sink_.result("particles", static_cast<double>(solver_.size()), "1", "material points");
  sink_.result("steps", static_cast<double>(s.steps), "1", "explicit time steps");
  if (s.steps > 0) {
    sink_.result("time_step_min", s.dtMin, "s", "smallest time step (eqs 25-26)");
    sink_.result("time_step_max", s.dtMax, "s", "largest time step (eqs 25-26)");
  }
  markers_.results(solver_, sink_);
  emitForces(stopped);
  emitMarkers(stopped);
  sink_.table("fracture", std::move(fracture_.table));
  inclusions_.report(sink_);
}

// Both energies, and KE/IE while the internal energy is at least 1 % of its largest value
// (before that the ratio of a tiny internal energy is a spike that says nothing; the energies
// plot shows that stretch).
void MpmRun::emitEnergy() {
  const auto ke = energy_.column("kinetic"), ie = energy_.column("internal");
  const double ieMax = ie.empty() ? 0.0 : *std::max_element(ie.begin(), ie.end());
  double maxRatio = 0.0;
  std::vector<double> ratio(ke.size(), std::numeric_limits<double>::quiet_NaN());  // NaN: not drawn
  for (std::size_t i = 0; i < ke.size(); ++i)
    if (ieMax > 0 && ie[i] >= 0.01 * ieMax) {
      ratio[i] = ke[i] / ie[i];
      maxRatio = std::max(maxRatio, ratio[i]);
    }
  sink_.result("max_ke_ie", maxRatio, "1",
               "largest kinetic / internal energy while the internal energy is >= 1 % of its maximum (eq 28; "
               "on a CFEMP insertion the points' noise can hold it at 0.1-0.25 at any mass scaling; the check that "
               "a run is quasi-static is to halve the mass scaling and compare the forces)");
  const auto time = energy_.column("time");
  io::Plot both{"Kinetic and internal energy", "time [s]", "energy [J]", {}};
  both.series.push_back({"kinetic", time, ke, false, false});
  both.series.push_back({"internal", time, ie, false, false});
  sink_.plot(std::move(both));
  io::Plot en{"Kinetic / internal energy, drawn where the internal energy is at least 1 % of its largest value",
              "time [s]", "KE / IE [-]", {}};
  en.series.push_back({"KE / IE", time, std::move(ratio), false, false});
  sink_.plot(std::move(en));
  sink_.table("energy", std::move(energy_));
}

// forces.csv, its plot and eq 35 against a measured curve.
void MpmRun::emitForces(bool stopped) {
  const io::Table& f = forces_.table();
  const auto depth = millimetres(f.column("depth"));
  io::Plot byDepth{"Insertion force against tip depth", "tip depth [mm]", "axial force on the needle [N]", {}};
  byDepth.series.push_back({"total", depth, f.column("force_total"), false, false});
  byDepth.series.push_back({"tip", depth, f.column("force_tip"), false, true});
  byDepth.series.push_back({"shaft (friction)", depth, f.column("force_shaft"), false, true});
  const MeasuredCurve& measured = spec_.measured_force;
  if (!measured.path.empty() && !stopped) {
    const auto e = mpm_outputs::compareForce(measured, f.column("depth"), f.column("force_total"));
    byDepth.series.push_back({"measured", millimetres(measured.depth), measured.force, true, false});
    if (e.n > 0) {
      sink_.result("rmse_force", e.rmse, "N", "RMSE of the total force against the measured curve (eq 35)");
      sink_.result("mae_force", e.mae, "N", "MAE of the total force against the measured curve (eq 35)");
      sink_.result("measured_points", static_cast<double>(e.n), "1", "measured points inside the simulated depths");
    } else {
      sink_.warning("The measured force curve has no point inside the simulated depths: no RMSE/MAE.");
    }
  }
  results::markLayerBoundaries(byDepth, sc_);
  sink_.plot(std::move(byDepth));
  sink_.table("forces", forces_.release());
}

// markers.csv, its plot and seed 000 eq 37 against the measured markers.
void MpmRun::emitMarkers(bool stopped) {
  if (markers_.empty()) return;
  io::Table& mt = markers_.table();
  io::Plot mp{"Marker displacement against depth (eq 36)", "tip depth [mm]", "in-plane displacement [mm]", {}};
  const auto md = millimetres(mt.column("depth"));
  for (const auto& n : markers_.names()) mp.series.push_back({n, md, millimetres(mt.column(n + "_uxy")), false, false});
  sink_.plot(std::move(mp));
  if (!spec_.measured_markers.path.empty() && !stopped) {
    std::vector<mpm::MarkerTrack> tracks;
    for (const auto& n : markers_.names()) tracks.push_back({n, mt.column(n + "_ux"), mt.column(n + "_uy")});
    const auto rows = mpm::compareMarkers(spec_.measured_markers, mt.column("depth"), tracks);
    io::Table et({{"depth", "m"}, {"r_max", "m"}, {"r_mean", "m"}, {"r_max_x", "m"}, {"r_max_y", "m"},
                  {"r_mean_x", "m"}, {"r_mean_y", "m"}, {"markers", "1"}});
    double worst = 0.0, worstMean = 0.0;
    for (const auto& r : rows) {
      et.addRow({r.depth, r.rmax, r.rmean, r.rmaxX, r.rmaxY, r.rmeanX, r.rmeanY, static_cast<double>(r.markers)});
      worst = std::max(worst, r.rmax);
      worstMean = std::max(worstMean, r.rmean);
    }
    if (!rows.empty()) {
      sink_.result("marker_r_max", worst, "m", "largest r_max of eq 37 over the measured depths");
      sink_.result("marker_r_mean", worstMean, "m", "largest r_mean of eq 37 over the measured depths");
      sink_.result("marker_measured_depths", static_cast<double>(rows.size()), "1",
                   "measured marker depths inside the simulated depths");
    } else {
      sink_.warning("The measured markers have no depth inside the simulated depths: no eq 37 errors.");
    }
    sink_.table("marker_errors", std::move(et));
  }
  sink_.table("markers", std::move(mt));
}

void MpmRun::runNotes(double seconds) {
  const auto& c = setup_.config;
  const MpmModelSpec& m = spec_;
  const TipType tip = sc_.needle.tip;
  const double rate = seconds > 0 ? static_cast<double>(sum_.steps - steps0_) * solver_.size() / seconds * 1e-6 : 0.0;
  sink_.note(fmt::format(
      "3D MPM of seed 000: {} material points ({:g} mm spacing), grid {} x {} x {} cells of {:g} mm, {} shape "
      "functions{}, {}, FLIP {:g}, k_t = {:g} (eq 26), mass scaling {:g} (eq 28); rigid {} needle R = {:g} mm, "
      "Coulomb friction of each layer and inclusion ({}). {} steps (dt {:.3g} to {:.3g} ms) in {:.3g} s on {} "
      "thread(s), {:.3g} M particle-steps/s (setup {:.2g} s). Force rows are impulse averages over the output "
      "interval. docs/models/mpm.md.",
      solver_.size(), m.particle_spacing * 1e3, c.cells[0], c.cells[1], c.cells[2], c.h * 1e3,
      m.bspline ? "quadratic B-spline" : "linear", m.fbar ? " with F-bar" : "", m.musl ? "MUSL" : "USL", m.flip,
      m.time_step_factor, m.mass_scaling,
      tip == TipType::Bevel ? "bevel" : tip == TipType::Conical ? "conical" : "blunt", setup_.needle.radius * 1e3,
      m.cfemp ? "CFEMP particle-to-surface contact with the triangulated needle, eqs 22-24" : "grid contact, eqs 14-21",
      sum_.steps, sum_.dtMin * 1e3, sum_.dtMax * 1e3, seconds, solver_.threads(), rate, setupSeconds_));
  if (solver_.onDevice()) sink_.note("The steps ran on the GPU (model.mpm.device: cuda, engines/mpm/cuda).");
  if (c.bodies == 2)
    sink_.note(fmt::format("Sliding inclusions are a second body in penalty contact with the tissue (Coulomb {:g}, "
                           "penalty_contact.hpp).",
                           c.friction));
  warnUnresolvedLateralForce();
  for (const auto& seg : sc_.insertion.segments)
    if (seg.kind == MotionSegment::Kind::Rotate && !seg.axial) {
      sink_.warning("In-plane base rotations are not modelled by mpm: the needle only translates along its axis.");
      break;
    }
}

// A bevel with the parting cut through the axis (model.mpm.cut: axis): the strip opens both lips
// by half the needle, where the bevel's sharp point leaves the wall-side lip in place and the face
// lifts the other by the whole needle. The wall pressure, and so the axial force, follows the total
// opening and agrees with explicit 3D; a symmetric opening presses both lips alike, so the cut has
// no bevel push to first order, and what is left, the difference of the two lips' pushes, points
// towards the face quasi-static (+26 mN on the reduced reference where explicit 3D gives -19 mN;
// docs/validation/agreement.md "Which lip moves").
void MpmRun::warnUnresolvedLateralForce() {
  const MpmModelSpec& m = sc_.model.mpm;
  if (sc_.needle.tip != TipType::Bevel || m.parting == "none" || m.cut != "axis") return;
  sink_.warning(
      "mpm's cut runs through the needle's axis (model.mpm.cut: axis): the axial force agrees with explicit 3D; the "
      "bevel's sideways push (force_lateral, and the tissue it moves across the needle) is not resolved: a cut that "
      "opens both lips alike has none, and what is left points towards the bevel's face, where every other engine "
      "pushes the needle away from it; cut: edges, which cuts where the bevel's edges pass, gives its sign "
      "(docs/validation/agreement.md \"Which lip moves\").");
}

}  // namespace needlesim::engines
