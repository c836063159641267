// Results of a run: HDF5 + XDMF time series for ParaView and summary.json.
// The writer is serial: the solver gathers fields to rank 0 (mesh numbering) and rank 0
// writes. Everything goes to a staging folder that replaces the output folder only when
// the run succeeds, so a failed run leaves nothing half-written behind.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/mesh.hpp"

namespace hs {

// A staging folder "<folder>.partial" that becomes <folder> on commit(); removed if the
// object dies uncommitted (an exception unwinds the run).
class OutputFolder {
 public:
  explicit OutputFolder(std::string folder);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  const std::string& staging() const { return staging_; }  // where files are written now
  const std::string& final() const { return final_; }      // where they end up
  void commit();

 private:
  std::string final_, staging_;
  bool committed_ = false;
};

struct StepFields {
  double time = 0;                   // load factor (static) or physical time (dynamic)
  std::vector<double> displacement;  // 3 per mesh node
  std::vector<double> nodal_load;    // 3 per mesh node: applied external load (gravity, pressure)
  std::vector<double> von_mises;     // per tetrahedron (Cauchy, at the centroid)
  std::vector<double> J;             // per tetrahedron (det F at the centroid)
  std::vector<int> rank;             // per tetrahedron: the MPI rank that owns it
};

// <folder>/<name>.h5 and <folder>/<name>.xmf. P2 meshes are written as Tetrahedron_10.
// write_step() refuses non-finite values (throws SolveError naming the field and entry):
// a NaN is never written as a result.
class XdmfWriter {
 public:
  XdmfWriter(const std::string& folder, const std::string& name, const Mesh& mesh);
  ~XdmfWriter();
  void write_step(const StepFields& fields);
  void close();                       // writes the .xmf; called by the destructor too
  std::string xdmf_file() const;      // file name (no folder) of the .xmf

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes JSON (pretty, 2 spaces) to path; throws SolveError if any number is not finite.
void write_json(const std::string& path, const nlohmann::json& j);

}  // namespace hs
