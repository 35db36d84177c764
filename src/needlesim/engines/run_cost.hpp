#pragma once
// The constants of the run-time estimate (engines/step_guard.hpp), in one place for every
// engine: the CPU seconds of a step on one thread from what it updates, of the set-up, and the
// threads' speed-up. Measured with scripts/example_times.py (one thread; CPU time = user + sys
// of the whole `needlesim run`, results folder included) on the shipped examples, then fitted
// per engine, never per example; docs/performance.md "Run-time estimates" gives the table, the
// command and the machine. On that machine every example lands within a factor 1.5 (the tests
// Estimates.*WithinAFactor1p5, label `timing`); on any machine each quick example within a factor
// 2 of the machine's median (Estimates.QuickExamplesWithinAFactor2OfTheMachine, in `make test`).
#include <algorithm>
#include <cmath>
#include <string>

#include "needlesim/engines/step_guard.hpp"

namespace needlesim::run_cost {

// Every run: start the program, read the scenario, write summary.json, tables and report.html.
inline constexpr double kRunSeconds = 0.12;

// The speed-up of `threads` threads over one: each added thread gives kParallelEfficiency of a
// thread (docs/performance.md "MPM thread scaling": 76-106 % at 2 threads, 57-68 % at 8).
inline constexpr double kParallelEfficiency = 0.8;
inline double speedUp(int threads) { return 1.0 + kParallelEfficiency * std::max(0, threads - 1); }

// lumped: a force evaluation and a row of the tables per step.
inline constexpr double kLumpedStep = 1.5e-6;

// realtime2d / realtime3d (docs/performance.md "Real-time 2D FE", "Real-time 3D FE"). The modal
// back-end (model.<engine>.solver auto: up to 2600 free DOFs) sets up by a dense
// eigendecomposition, ~ DOFs^3, and steps in every mode, ~ DOFs; the reduced one sets up by a
// sparse Cholesky and Lanczos, ~ nodes (2D) or nodes^1.22 (3D: 10.5k and 25k-node blocks), and
// steps on the path nodes alone.
inline constexpr double kModalSetupPerDof3 = 6.2e-10;  // re-measured at load 1-3 (2026-11-28)
inline constexpr double kModalStepPerDof2d = 5.7e-8;
inline constexpr double kModalStepPerDof3d = 1.33e-7;
inline constexpr int kModalMaxDofs = 2600;  // realtime/tissue_dynamics.hpp modal_max_dofs
inline constexpr double kReducedSetupPerNode2d = 1.1e-4;
inline constexpr double kReducedSetupPerNode3d = 4.3e-5;  // s, times nodes^kReducedSetupPower3d
inline constexpr double kReducedSetupPower3d = 1.22;
inline constexpr double kReducedStep2d = 2.0e-5;
// 3D: the step with up to kCoupledPointsRef coupled points; beyond, the dense coupled system of
// 3 unknowns per point grows the step as points^2 (docs/performance.md "Real-time 3D FE": 26 us
// at 27 points, 139 us at 54 on the bench block; whole runs with 60 points 300-400 us a step).
inline constexpr double kReducedStep3d = 6.0e-5;
inline constexpr double kCoupledPointsRef = 27.0;
inline constexpr double kDirectStepPerNode = 4.5e-7;  // the sparse LDLT solve, 4.5 ms at 10k nodes

// A real-time engine's plan costed for `solver` (auto, direct, modal, reduced) on a mesh of
// `nodes` with `freeDofs` free DOFs in `dim` dimensions (3D: `coupledPoints` needle points at most).
inline void costRealtime(StepPlan& p, const std::string& solver, int dim, double nodes, double freeDofs,
                         double coupledPoints = 0.0) {
  const bool modal = solver == "modal" || (solver == "auto" && freeDofs <= kModalMaxDofs);
  if (modal) {
    p.setupSeconds = kModalSetupPerDof3 * freeDofs * freeDofs * freeDofs;
    p.secondsPerStep = (dim == 2 ? kModalStepPerDof2d : kModalStepPerDof3d) * freeDofs;
    return;
  }
  p.setupSeconds = dim == 2 ? kReducedSetupPerNode2d * nodes
                            : kReducedSetupPerNode3d * std::pow(nodes, kReducedSetupPower3d);
  const double r = std::max(1.0, coupledPoints / kCoupledPointsRef);
  p.secondsPerStep = solver == "direct" ? kDirectStepPerNode * nodes
                     : dim == 2         ? kReducedStep2d
                                        : kReducedStep3d * r * r;
}

// kinematic, energy, beam-foundation: one increment of the needle's path.
inline constexpr double kSteeringStep = 2.0e-5;

// explicit: one element's internal force per step, by element (plane quad4/tri3, hex8, tet4),
// and the set-up (mesh, masses, cohesive surfaces; the bonded tip's assembly and factorisation) per
// element.
inline constexpr double kExplicitPlaneElement = 1.6e-7;
inline constexpr double kExplicitHex8Element = 3.1e-7;
inline constexpr double kExplicitTet4Element = 1.25e-7;
inline constexpr double kExplicitSetupPerElement = 1.0e-5;

// mpm: one material point per step (scatter, grid update, gather, stress) and its set-up and
// field output. Eq 26's step shrinks as the tissue the needle compresses stiffens: a run takes
// kMpmGrowth times the first step's count, plus, for a strain-stiffening (Fung) tissue,
// k x (travel / h) x (d_c / h) (h the grid spacing, d_c the needle's diameter plus CFEMP's
// model.mpm.cfemp_element_size, eq 22's reach), k by contact kind: kMpmGrowthPloughing where the
// needle pushes the tissue aside (a conical tip, or parting: none), kMpmGrowthParting where a
// bevel parts it along its cut with grid contact, and with CFEMP, whose parted lips hardly
// stiffen in a wide block, kMpmGrowthCfempParting + kMpmGrowthCfempDrag x the block's drag strain
// mu_f pi d_c travel / (width x height) (the shaft's friction compresses a narrow block). A
// sliding inclusion's pair contact (shorter steps, and the pair search each step) costs
// kMpmSliding times more. Measured: neo-Hookean tissues 1.02-1.10 times the first step's count;
// Fung, ploughing 2.0-5.7 (k 0.19-0.20: quick_needle_block, global_model, seed000_fracture_onset);
// grid-contact parting k 0.04 (organ_block_1m shortened, grid contact); CFEMP parting k 0.0026 at
// drag strain 0.010 (organ_block_1m, 1341 steps for 1086), 0.0028 at 0.065 (the same, 30 x 20 x 20
// mm), 0.011-0.013 at 0.26 (50 and 30 x 10 x 10 mm) and 0.017 at 0.26 (local_model); the sliding
// tumour of tumour_target (the one example with a sliding interface): 2.9 times the first step's
// count at 1.5 times the cost per point-step of the others.
inline constexpr double kMpmPoint = 1.05e-7;
inline constexpr double kMpmSetupPerPoint = 2.0e-6;
inline constexpr double kMpmGrowth = 1.15;
inline constexpr double kMpmGrowthPloughing = 0.2;
inline constexpr double kMpmGrowthParting = 0.04;
inline constexpr double kMpmGrowthCfempParting = 0.0022;
inline constexpr double kMpmGrowthCfempDrag = 0.045;
inline constexpr double kMpmSliding = 2.2;
// mpm's needle contact per step, beyond kMpmPoint (the passes and grid contact), from `perf
// record` on one thread of organ_block_1m (1e6 points: the scans 6 % each of the step), of it in a
// 50 x 10 x 10 mm block and of local_model (the facet tests 15-20 %, the strip 3-4 %): the parting
// cut (needle_cut.cpp) tests every point against the cut's strip (kMpmCutScan) and, for the points
// within a support's reach of it, each support node's segment, and gives them renormalised
// supports in the passes (kMpmCutStripPoint); CFEMP (cfemp_contact.cpp, serial) puts every point in
// the needle frame and its bucket (kMpmCfempScan) and tests the points in the needle's buckets
// against each facet there (kMpmFacetTest per point and facet), along the needle's mean length in
// the tissue. kMpmPoint is the rest of those steps (105-115 ns a point-step) and of
// global_model's (grid contact).
inline constexpr double kMpmCutScan = 8.0e-9;
inline constexpr double kMpmCutStripPoint = 7.0e-8;
inline constexpr double kMpmCfempScan = 1.0e-8;
inline constexpr double kMpmFacetTest = 8.0e-9;

}  // namespace needlesim::run_cost
