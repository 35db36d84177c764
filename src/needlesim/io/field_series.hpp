#pragma once
// Field time series for ParaView: one HDF5 file with the arrays and one XDMF
// file that describes them (open the .xdmf in ParaView; meshio's XDMF
// TimeSeriesReader reads it too). The XDMF is rewritten atomically after every
// step, so a run that stops part-way leaves every completed step readable.
// Layout (docs/results.md "Field files"): points with 3 coordinates (a 2D series
// has z = 0), connectivity for every cell type (one Polyvertex per point for
// CellType::Points), vectors of a 2D series with 3 components (z = 0), every
// dataset with a string attribute `units`, every XDMF array named "name [unit]" but the integer
// labels ("region") and "displacement", whose units are in their `units` attribute only. The
// points of every step are the reference mesh's unless stepPoints moves them (the needle), so
// Warp By Vector by the displacement gives the deformed shape.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace needlesim::io {

class BinaryWriter;
class BinaryReader;

enum class CellType { Points, Triangle, Quad, Tetra, Hexa, Line };

class FieldSeries {
 public:
  // dim: 2 or 3 coordinates per point.
  FieldSeries(std::filesystem::path h5, std::filesystem::path xdmf, int dim);
  ~FieldSeries();
  FieldSeries(const FieldSeries&) = delete;
  FieldSeries& operator=(const FieldSeries&) = delete;

  // Reference mesh (points dim x n, cells as flat connectivity). For
  // CellType::Points the connectivity may be empty (one vertex per point).
  void setMesh(const std::vector<double>& points, CellType type, const std::vector<int>& connectivity);

  // A constant integer array on the points (after setMesh; one value per point), e.g. the
  // region each particle belongs to: dataset /mesh/point/<name> (int32, units "1", and the
  // string attribute `names` = `legend`), shown at every step as "<name>".
  void meshPointLabels(const std::string& name, const std::vector<int>& values, const std::string& legend);

  // The same for the cells (one value per cell): dataset /mesh/cell/<name>, shown as "<name>".
  void meshCellLabels(const std::string& name, const std::vector<int>& values, const std::string& legend);

  void beginStep(double time);
  // Moved points for this step (a rigid body that moves, the needle), as many as the mesh's. Optional;
  // a deforming body keeps its reference points and writes its displacement.
  void stepPoints(const std::vector<double>& points);
  // Point or cell data: `components` values per point/cell (1 scalar, dim vector, 6 symmetric
  // tensor) in `unit` (SI, as the tables: "m", "m/s", "Pa", "1").
  void pointData(const std::string& name, const std::vector<double>& values, int components, const std::string& unit);
  void cellData(const std::string& name, const std::vector<double>& values, int components, const std::string& unit);
  // Flushes the step to the disk and rewrites the XDMF. Every write that fails
  // (disk full, file size limit) throws Error naming the file.
  void endStep();
  // Closes the HDF5 file (the destructor closes it too, silently); throws
  // Error when the last data could not be written.
  void close();

  std::size_t steps() const;
  const std::filesystem::path& xdmfPath() const;

  // Checkpoints (results/checkpoint.hpp): saveState writes the series so far (its
  // steps and datasets) into `w` and a copy of the HDF5 file to `h5copy`
  // (through a temporary file, renamed); restore continues the series from
  // such a copy, replacing whatever this series holds, and rewrites the XDMF.
  void saveState(BinaryWriter& w, const std::filesystem::path& h5copy) const;
  void restore(BinaryReader& r, const std::filesystem::path& h5copy);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace needlesim::io
