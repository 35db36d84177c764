#pragma once
// The typed scenario every engine receives: plain structs in SI units.
// Engines never parse YAML; scenario/reader.cpp builds this from a file.
#include <string>
#include <vector>

#include "needlesim/materials/material_spec.hpp"

namespace needlesim {

// Modified Karnopp friction along the shaft, per unit length in contact
// (seed 003 eq 3.23 with the per-length coefficients of eq 5.1).
struct FrictionSpec {
  double C_p = 0.0;          // N/m, dynamic friction, insertion
  double b_p = 0.0;          // N s/m^2, damping, insertion
  double C_n = 0.0;          // N/m, dynamic friction, retraction (magnitude)
  double b_n = 0.0;          // N s/m^2, damping, retraction
  double D_p = 0.0;          // N/m, static friction limit, positive direction
  double D_n = 0.0;          // N/m, static friction limit, negative direction (magnitude)
  double static_band = 0.0;  // m/s, Delta v: |v| < Delta v/2 counts as sticking
  double coefficient = 0.0;  // Coulomb coefficient for contact engines (seed 001: 0.3)
};

struct LayerSpec {
  std::string name;
  double thickness = 0.0;            // m, along the surface normal
  materials::MaterialSpec material;  // constitutive law
  double puncture_force = 0.0;       // N, threshold of the pre-puncture stiffness force
  double cutting_force = 0.0;        // N, constant cutting force (seed 003 eq 3.24)
  FrictionSpec friction;
  double interaction_stiffness = 0.0;  // N/m^2, K_T (seed 002 eq 13); 0 = not given
  double toughness = 0.0;              // J/m^2, rupture toughness G_c; 0 = not given
};

struct TissueSpec {
  double length = 0.0;  // m, block extent along the insertion axis (entry face to exit face)
  double width = 0.0;   // m
  double height = 0.0;  // m
  std::vector<LayerSpec> layers;  // stacked from the entry face; thicknesses sum to length
};

enum class TipType { Bevel, Conical, Blunt };

struct NeedleSpec {
  double outer_diameter = 0.0;  // m
  double inner_diameter = 0.0;  // m (0 = solid)
  double length = 0.0;          // m
  double bevel_angle = 0.0;     // rad (tip angle alpha)
  TipType tip = TipType::Bevel;
  double youngs_modulus = 0.0;  // Pa
  double poisson = 0.3;
  double density = 0.0;  // kg/m^3
};

struct MotionSegment {
  enum class Kind { Insert, Pause, Retract, Rotate };
  Kind kind = Kind::Insert;
  double speed = 0.0;       // m/s, > 0 (Insert, Retract)
  double to_depth = 0.0;    // m, needle tip depth along its axis at the end (Insert, Retract)
  double duration = 0.0;    // s (Pause; Rotate derived from angle/rate)
  double angle = 0.0;       // rad (Rotate)
  double rate = 0.0;        // rad/s (Rotate; spin rate while inserting)
  bool axial = true;        // Rotate: about the needle axis (bevel) or in the insertion plane (base)
  double duty_cycle = 0.0;  // Insert: fraction of time spinning (0 = no spinning)
};

struct InsertionSpec {
  double entry_angle = 1.5707963267948966;  // rad, between needle and surface (90 deg = normal)
  double entry_offset = 0.0;                // m, entry point from the centre of the entry face
  double start_depth = 0.0;                 // m, tip position at t = 0 (negative = outside)
  double bevel_orientation = 0.0;           // rad, initial axial orientation of the bevel
  std::vector<MotionSegment> segments;
};

struct LumpedModelSpec {
  double relaxation_time = 0.0;  // s, decay of the held friction during pauses (0 = none)
};

struct ModelSpec {
  std::string engine = "lumped";  // lumped (others are listed in docs/scenario-format.md)
  double time_step = 1e-3;        // s, output and integration step
  LumpedModelSpec lumped;
};

struct OutputSpec {
  std::string directory;    // empty = results/<scenario name>
  double interval = 0.0;    // s, sampling interval of the time series (0 = every step)
  bool html = true;
  bool csv = true;
};

struct Scenario {
  std::string name = "scenario";
  std::string description;
  std::string source;  // file it came from, or "<built-in default>"
  TissueSpec tissue;
  NeedleSpec needle;
  InsertionSpec insertion;
  ModelSpec model;
  OutputSpec output;

  // The tip depth at the end of the motion profile and the largest reached.
  double maxDepth() const;
  double totalDuration() const;
};

}  // namespace needlesim
