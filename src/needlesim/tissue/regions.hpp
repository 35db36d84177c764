#pragma once
// Tissue regions: the layers, then the inclusions, each with its material, its Coulomb coefficient
// of needle contact and its rupture toughness. Region r < layers is layer r, region layers + i is
// inclusion i. The one resolution of layers and inclusions that the engines meshing the tissue
// (explicit, mpm) share: solver materials, friction per node or particle, the cohesive law's G_c.
#include <string>
#include <vector>

#include "needlesim/materials/material_spec.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::tissue {

struct Region {
  std::string name;
  std::string field;  // the scenario field that declares it: "tissue.layers[0]", "tissue.inclusions[1]"
  materials::MaterialSpec material;
  double friction = 0.0;   // Coulomb coefficient of needle contact
  double toughness = 0.0;  // J/m^2, rupture toughness G_c; 0 = not given
  bool inclusion = false;
};

// Layers in order, then inclusions in order.
std::vector<Region> regions(const TissueSpec& t);
std::vector<materials::MaterialSpec> regionMaterials(const std::vector<Region>& r);
std::vector<double> regionFrictions(const std::vector<Region>& r);
// True when every region has the same Coulomb coefficient (one coefficient holds everywhere).
bool uniformFriction(const std::vector<Region>& r);
// Region of a point of the tissue frame (x depth from the entry face): the last inclusion that contains
// it (later ones are laid over earlier ones), else the layer at its depth.
int regionAt(const TissueSpec& t, double x, double y, double z);
// Region of every cell of a mesh in the tissue frame (`dim` coordinates per point, 2D at z = 0; `perCell`
// nodes per cell in `conn`): an imported geometry's element regions where the mesh is that geometry's
// (as many cells), else the region at the cell's centroid, as the engines assign materials.
std::vector<int> cellRegions(const TissueSpec& t, const std::vector<double>& points, int dim,
                             const std::vector<int>& conn, int perCell);
// The names of the regions, for the `names` attribute of a region array: "0 skin, 1 fat, 2 tumour".
std::string regionLegend(const TissueSpec& t);

}  // namespace needlesim::tissue
