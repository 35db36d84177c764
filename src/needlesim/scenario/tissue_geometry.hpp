#pragma once
// tissue.geometry: an imported tissue geometry read, scaled by its unit and placed in the tissue
// frame (docs/scenario-format.md "Imported geometry"). Internal to the reader, in the order it
// calls them: place the mesh (the block becomes its bounding box), map its groups to the
// scenario's layers and inclusions by name, hold its far side, and find where the needle path
// enters it.
#include <memory>
#include <set>
#include <string>

#include "needlesim/scenario/scenario.hpp"
#include "needlesim/scenario/yaml_section.hpp"

namespace needlesim::scenario {

// Imports the file or surfaces of section `g` (tissue.geometry), scales them by `unit`, rotates
// and translates them, and checks that the size fits the unit and that the body lies beyond the
// entry plane x = 0. Sets the block of `T` to the smallest centred one that holds the mesh.
std::shared_ptr<ImportedGeometry> placeGeometry(Section& g, const std::string& source, TissueSpec& T);

// The names of the mesh's groups (bodies); unnamed groups are left out.
std::set<std::string> groupNames(const ImportedGeometry& geometry);

// Element regions from the group names (docs/scenario-format.md): a group named like an inclusion
// is that inclusion, one named like a layer that layer; with one layer, every other group is it.
// Fills each mesh inclusion's centroid, equivalent radius and, where not given, the friction and
// toughness of the layer around it. `t` is the tissue section, for errors.
void mapRegions(ImportedGeometry& geometry, TissueSpec& T, Section& t);

// Nodes of the boundary facing away from the needle (outward normal within 60 deg of +x) within
// tissue.geometry.support_depth of the deepest point.
void markSupport(ImportedGeometry& geometry, Section& g);

// Where the needle axis first meets the tissue; InputError when the path misses it or the
// profile never reaches it.
void findEntry(ImportedGeometry& geometry, const InsertionSpec& insertion, double maxDepth, Section& ins);

}  // namespace needlesim::scenario
