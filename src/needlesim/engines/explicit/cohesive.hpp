#pragma once
// Cohesive zone for the explicit engine (docs/models/cohesive.md).
//
// Law: bilinear traction-separation (seed 001 eqs 5-6, seed 004 eq 14 and
// Fig 9b) with one initial stiffness K = K_n = K_s (seed 004), normal and
// shear strengths t_c, s_c and fracture energies G_Ic, G_IIc. Mixed mode as
// Camanho, Davila & de Moura (2003, J. Compos. Mater. 37:1415): effective
// separation delta_m = sqrt(<delta_n>^2 + delta_s^2), quadratic initiation
// (<t_n>/t_c)^2 + (t_s/s_c)^2 = 1 and the linear energy criterion
// G_I/G_Ic + G_II/G_IIc = 1 for full separation. Scalar damage
// d = delta_f (delta_max - delta_0) / (delta_max (delta_f - delta_0)),
// irreversible (d never decreases, no healing); unloading follows the damaged
// secant (1 - d) K; compression is the undamaged penalty K (no
// interpenetration of the crack faces, also after full damage); d = 1 is an
// open crack (traction-free in tension and shear).
//
// Interface: 2D zero-thickness line elements on the node pairs of the
// engine's seam (mesh.hpp splitSeam), integrated at the nodes (Newton-Cotes /
// lumped: each pair carries its tributary reference length), which avoids the
// spurious traction oscillations of Gauss integration in stiff interfaces.
// Separation in the current mid-surface frame; the forces enter the explicit
// force balance next to the internal forces; the work, stored energy and
// dissipated energy are tracked for the energy balance.
#include <Eigen/Core>
#include <array>
#include <limits>
#include <utility>
#include <vector>

namespace needlesim::explicit_fe {

struct CohesiveLaw {
  double stiffness = 0.0;       // K = K_n = K_s, Pa/m (traction per separation)
  double strength = 0.0;        // t_c, normal strength, Pa
  double shearStrength = 0.0;   // s_c, Pa (0 = t_c)
  double energy = 0.0;          // G_Ic, J/m^2
  double shearEnergy = 0.0;     // G_IIc, J/m^2 (0 = G_Ic)

  double sc() const { return shearStrength > 0 ? shearStrength : strength; }
  double G2() const { return shearEnergy > 0 ? shearEnergy : energy; }
  double delta0() const { return strength / stiffness; }      // normal onset separation
  double deltaF() const { return 2.0 * energy / strength; }   // normal final separation (seed 001 eq 6)
  // Seed 004 section IV-A: K_n = K_s = E / T0 (T0 = constitutive thickness, the
  // paper's "unit original constitutive thickness"), t_c = 2 G_c / delta_c.
  static CohesiveLaw fromCriticalSeparation(double E, double T0, double Gc, double deltaC);
  // Throws Error unless every parameter is positive and delta_0 < delta_f in both modes.
  void validate() const;
};

struct CohesiveState {
  double damage = 0.0;
  double dissipated = 0.0;  // J/m^2
  double Yprev = 0.0;       // 1/2 K delta_m^2 at the previous update (diagnostic)
};

struct CohesiveTraction {
  double tn = 0.0, ts = 0.0;  // Pa, on the upper face's separation (resisting)
  double stored = 0.0;        // J/m^2, recoverable energy density
};

// Traction at separation (dn, ds); updates damage and dissipation irreversibly.
// Dissipation increment int Y dd with Y = 1/2 K delta_m^2, integrated exactly along the
// softening branch of the current mode ratio (closed form, step-size independent).
CohesiveTraction cohesiveUpdate(const CohesiveLaw& law, double dn, double ds, CohesiveState& st);
// Mixed-mode onset and final effective separations for mode ratio beta = ds / dn (dn > 0).
void cohesiveMixedMode(const CohesiveLaw& law, double dn, double ds, double& d0, double& df);

struct Mesh;

// Zero-thickness interface on seam node pairs (a on the lower face, b on the
// upper face; reference normal from a's side to b's side): 2D line elements
// (constructor) or 3D quadrilaterals (surface3D, cohesive_surface.cpp).
class CohesiveInterface {
 public:
  // pairs in any order; they are sorted along `direction` (the seam's reference
  // tangent); the normal is `direction` turned +90 deg. `laws` has one entry per
  // pair (same order as `pairs`) or a single entry for all. `thickness`: the
  // out-of-plane extent (2D per metre: 1).
  CohesiveInterface(const std::vector<double>& X, const std::vector<std::pair<int, int>>& pairs,
                    std::vector<CohesiveLaw> laws, Eigen::Vector2d direction = Eigen::Vector2d::UnitX(),
                    double thickness = 1.0);

  // 3D zero-thickness quadrilaterals on the seam plane of a hex8 mesh (after
  // splitSeam): every hex face on the +refNormal side whose 4 nodes lie on the
  // seam plane and hold at least one copy node b is a cohesive quad; unsplit
  // nodes on its border are closed (zero separation). Nodal (Newton-Cotes)
  // integration: each pair carries int N_a dA of its quads (reference, 2x2
  // Gauss), "tributary area" (tributaryLength() in 3D). Frame per pair: the
  // normal of the current mid-surface (mean of its quads' diagonal cross
  // products), shear = the in-plane rest of the separation (isotropic).
  // position(p) = reference coordinate along `direction`.
  static CohesiveInterface surface3D(const Mesh& mesh, const std::vector<std::pair<int, int>>& pairs,
                                     std::vector<CohesiveLaw> laws, Eigen::Vector3d refNormal,
                                     Eigen::Vector3d direction);

  // 3D quadrilaterals given explicitly (a curved seam, e.g. the cylindrical sleeve of mesh_sleeve.hpp):
  // each quad lists 4 mesh nodes in cyclic order, the copy b of a pair or an unsplit node (closed
  // front), with its reference normal (a's side to b's side; only its sign relative to the quad's
  // diagonal cross product is used). Same nodal integration and per-pair current frame as surface3D.
  static CohesiveInterface fromQuads(const Mesh& mesh, const std::vector<std::pair<int, int>>& pairs,
                                     std::vector<CohesiveLaw> laws, const std::vector<std::array<int, 4>>& quadNodes,
                                     const std::vector<Eigen::Vector3d>& quadRefNormals, Eigen::Vector3d direction);

  // Extra tributary length at the first / last pair (half the segment to a
  // shared, unsplit node beyond the seam's end: a closed crack tip).
  void addEndLength(double first, double last);
  // Adds the cohesive forces (on the nodes) for displacement u (2 per node) to f.
  // Returns nothing; energies are updated (stored, dissipated).
  void addForces(const std::vector<double>& X, const std::vector<double>& u, std::vector<double>& f);
  // Largest natural frequency squared of a pair spring, K L w (1/m_a + 1/m_b).
  double maxOmega2(const std::vector<double>& nodalMass) const;

  int pairs() const { return static_cast<int>(a_.size()); }
  int dim() const { return dim_; }
  int quads() const { return static_cast<int>(quad_.size()); }
  int node(int p, int side) const { return side == 0 ? a_[p] : b_[p]; }
  double tributaryLength(int p) const { return len_[p]; }  // 3D: tributary area
  double position(int p) const { return s_[p]; }  // reference coordinate along the seam
  const CohesiveState& state(int p) const { return st_[p]; }
  const CohesiveLaw& law(int p) const { return law_[p]; }
  double separationNormal(int p) const { return dn_[p]; }
  double stored() const { return stored_; }          // J (2D: per `thickness`)
  double dissipated() const { return dissipated_; }  // J
  int fullyDamaged() const;
  // Reference length (3D: area) with d = 1 and its farthest position along the seam (crack tip).
  double crackedLength() const;
  double crackTip(double threshold = 1.0 - 1e-12) const;
  // Marks pairs as fully damaged (e.g. passed by the tip with release enabled); their
  // remaining stored energy counts as dissipated.
  void forceOpen(int p);

 private:
  CohesiveInterface() = default;
  void addForces3D(const std::vector<double>& X, const std::vector<double>& u, std::vector<double>& f);
  int dim_ = 2;
  // 3D: per quad its 4 corners (pair index >= 0, or -1 - node for an unsplit node), the sign
  // that turns its diagonal cross product to the reference normal; per pair its quads (CSR).
  std::vector<std::array<int, 4>> quad_;
  std::vector<double> quadSign_;
  std::vector<int> pairQuadStart_, pairQuads_;
  Eigen::Vector3d refNormal3_ = Eigen::Vector3d::UnitY();
  std::vector<double> quadNormal_;  // work array: 3 per quad
  std::vector<int> a_, b_;
  std::vector<double> len_, s_, dn_;
  std::vector<CohesiveLaw> law_;
  std::vector<CohesiveState> st_;
  std::vector<double> psi_;  // stored J/m^2 per pair
  Eigen::Vector2d dir_;
  double w_ = 1.0, stored_ = 0.0, dissipated_ = 0.0;
};

}  // namespace needlesim::explicit_fe
