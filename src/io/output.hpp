// Results of a run: HDF5 + XDMF time series for ParaView and summary.json.
// The writer is parallel: every rank writes its own rows of every dataset (its owned nodes,
// its tetrahedra) into the one .h5 with collective MPI-IO writes; rank 0 writes the .xmf.
// Nothing is gathered. Everything goes to a staging folder that replaces the output folder only
// when the run succeeds; a run that fails after some steps leaves them in "<folder>.failed"
// (with an .xmf that names only those steps), never over an earlier good result.
#pragma once

#include <mpi.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/folder_lock.hpp"
#include "mesh/mesh.hpp"

namespace hs {

// Why `folder` cannot serve as an output folder, or "" if it can: it, or its .partial, .old
// or .failed sibling, exists and is not ours to delete; it, a sibling or its .lock is a
// symbolic link; its name ends in .partial, .failed, .old or .lock (the names of another
// folder's run); its name or path is too long for the names a run makes; it is . or ..
// parse_deck checks output.folder with it on every rank, before any work.
std::string output_folder_problem(const std::string& folder);

// A staging folder "<folder>.partial" that becomes <folder> on commit(); removed if the
// object dies uncommitted (an exception unwinds the run). An existing <folder> is replaced
// (deleted) on commit, so it must be empty or an earlier hydrosoft output folder (marked
// by the file .hydrosoft_output): the constructor throws InputError otherwise. The folder is
// locked for the object's life (FolderLock, "<folder>.lock"): while one run holds it, the
// constructor of another throws InputError saying that another run is writing the folder,
// before it deletes or creates anything.
class OutputFolder {
 public:
  explicit OutputFolder(std::string folder);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  const std::string& staging() const { return staging_; }  // where files are written now
  const std::string& final() const { return final_; }      // where they end up
  void commit();
  // A failed run: the staging folder becomes "<folder>.failed" (replacing an earlier run's);
  // <folder> is left as it is. Returns the new path.
  std::string keep_failed();

 private:
  std::string final_, staging_;
  std::unique_ptr<FolderLock> lock_;
  bool committed_ = false, kept_ = false;
};

// The rows of the output one rank writes: its owned nodes and its tetrahedra. Rank r's rows
// follow rank r-1's, so the file's nodes are in the solver's numbering; /mesh/node_ids and
// /mesh/tet_ids give each row's number in the mesh file (identity on one rank).
struct OutputLayout {
  int order = 1;
  int64_t nodes = 0, tets = 0;             // of the whole mesh
  int64_t first_node = 0, first_tet = 0;   // this rank's first rows
  std::vector<double> x;                   // its nodes' reference coordinates, 3 each
  std::vector<int64_t> topology;           // its tetrahedra, in file rows (gmsh node order)
  std::vector<int64_t> node_ids, tet_ids;  // numbers in the mesh file of its rows
  // Physical groups, for ParaView's selections: per tetrahedron its volume group's index in
  // volume_names; per named surface, curve or point group (every rank the same list, in the
  // same order) a 0/1 mask over its nodes.
  std::vector<int> volume_group;
  std::vector<std::string> volume_names;
  struct NodeGroup {
    std::string name;
    std::vector<int> mask;  // 1 per node of its rows in the group, else 0
  };
  std::vector<NodeGroup> node_groups;
  int64_t my_nodes() const { return static_cast<int64_t>(node_ids.size()); }
  int64_t my_tets() const { return static_cast<int64_t>(tet_ids.size()); }
};

// The layout of a whole mesh written by one process.
OutputLayout whole_layout(const Mesh& mesh);

struct StepFields {
  double time = 0;  // load factor (static) or physical time (dynamic)
  // What `time` is: load_factor, time_s, state (index plus fraction) or target_set.
  std::string time_kind = "load_factor";
  std::vector<double> displacement;  // 3 per node of this rank's rows
  std::vector<double> nodal_load;    // 3 per node: applied external load (gravity, pressure)
  // Parts of nodal_load, 3 per node, written only when not empty (decks with cavities, resp.
  // a liquid's weight): the cavities' pressure on their walls, the liquid's weight.
  std::vector<double> cavity_pressure_load, fluid_weight_load;
  std::vector<double> von_mises;  // per tetrahedron of its rows (Cauchy, at the centroid)
  std::vector<double> J;          // per tetrahedron (det F at the centroid)
  // Tensors at the centroid, written only when not empty (all four together): per
  // tetrahedron the Cauchy stress and the Green-Lagrange strain (9 each, row-major: xx xy xz
  // yx ... zz) and their principal values (3 each, largest first).
  std::vector<double> stress, strain, principal_stress, principal_strain;
  // Bodies of the nodal-pressure element only (written when not empty): per node, the
  // volumetric stress of its patch, positive in compression (-k ln J_a / J_a).
  std::vector<double> pressure;
  std::vector<int> rank;  // per tetrahedron: the MPI rank that owns it
  // Further per-node fields, each written when given (decks with obstacles: contact_gap,
  // contact_pressure, friction_traction; with contact.self: self_contact_gap,
  // self_contact_pressure; docs/output.md): `components` values per node.
  struct NodeField {
    std::string name;
    int components = 1;
    std::string units;
    std::vector<double> values;
  };
  std::vector<NodeField> node_fields;
};

// <folder>/<name>.h5 and <folder>/<name>.xmf (layout: docs/output.md). P2 meshes are
// written as Tetrahedron_10 in VTK's node order. write_step() refuses non-finite values
// (throws SolveError on every rank, naming the field and the mesh's node or tetrahedron): a
// NaN is never written as a result. The .xmf is rewritten (atomically) after every step: a
// step exists once the .xmf names it. A file that cannot be written (a full disk) throws
// SolveError on every rank, naming the file and the reason; a step refused so leaves the
// files as they were after the previous one (the .h5 may hold an unnamed group of it). With a
// communicator every call is collective; `folder` must be the same path on every rank.
class XdmfWriter {
 public:
  XdmfWriter(const std::string& folder, const std::string& name, const Mesh& mesh);
  XdmfWriter(MPI_Comm comm, const std::string& folder, const std::string& name,
             OutputLayout layout);
  ~XdmfWriter();
  void write_step(const StepFields& fields);
  void close();                   // no more steps (the .xmf names every step written)
  std::string xdmf_file() const;  // file name (no folder) of the .xmf
  std::string h5_file() const;    // file name (no folder) of the .h5

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Writes JSON (pretty, 2 spaces) to path, atomically; throws SolveError naming the key
// (e.g. time_s.total) if any number is not finite.
void write_json(const std::string& path, const nlohmann::json& j);

}  // namespace hs
