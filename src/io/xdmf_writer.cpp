// XdmfWriter: one HDF5 file with the mesh once and the fields of every step, and an XDMF
// file that ParaView reads (docs/output.md). Layout of <name>.h5:
//   /mesh/coordinates  N x 3 float64      /mesh/topology  E x 4 or E x 10 int64 (VTK order)
//   /mesh/node_ids  N int64, /mesh/tet_ids  E int64 (the rows' numbers in the mesh file)
//   /step_<k>/displacement, nodal_load  N x 3 float64;  von_mises, J  E float64;
//   stress, strain  E x 9 float64 (Cauchy, Green-Lagrange; row-major 3 x 3),
//   principal_stress, principal_strain  E x 3 float64 (largest first);
//   /step_<k>/rank  E int32;  attributes /step_<k>/time, time_kind;
//   with cavities /step_<k>/cavity_pressure_load (and with a liquid's weight
//   fluid_weight_load)  N x 3 float64, the parts of nodal_load they are.
//   /mesh/volume_group  E int32, /mesh/group_<name>  N int32 0/1 (physical groups).
// Every dataset has a string attribute `units` (m, N, Pa or 1).
// The .xmf is a Temporal collection of Uniform grids, each with its own <Time Value=.../>
// (ParaView 5.11's Xdmf3 readers abort on a <Time TimeType="List"> on the collection), all
// pointing at the same /mesh datasets. It is rewritten atomically after every step, so the
// staging folder of a run that is still going (or died) can be opened.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5_file.hpp"
#include "io/output.hpp"
#include "io/write_together.hpp"

namespace hs {

struct XdmfWriter::Impl {
  MPI_Comm comm = MPI_COMM_NULL;  // null: serial
  int rank = 0;
  std::string folder, name;
  int nodes_per_tet = 4;
  int64_t nodes = 0, tets = 0;
  int64_t first_node = 0, first_tet = 0, my_nodes = 0, my_tets = 0;
  std::vector<int64_t> node_ids, tet_ids;
  std::vector<double> times;  // of the steps written so far
  std::vector<std::string> time_kinds;
  std::vector<char> has_pressure, has_weight, has_tensors;  // per step: its optional fields
  std::vector<char> has_nodal_pressure;
  // Per step: the further node fields' names and components (StepFields::node_fields).
  std::vector<std::vector<std::pair<std::string, int>>> node_fields;
  std::vector<std::string> mask_names;  // /mesh/group_<name> datasets
  bool closed = false;

  std::string h5_path() const { return folder + "/" + name + ".h5"; }
  std::string xmf_path() const { return folder + "/" + name + ".xmf"; }
  // The XML of one Uniform grid: step k, or the mesh alone (step -1).
  std::string grid(const std::string& indent, int step) const;
  double time_value(int step) const;  // the <Time Value> of step k
  void write_xdmf() const;
  std::string xdmf_text() const;
};

namespace {

std::string number_text(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

std::string escape_xml(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// One HDF5 dataset as an XDMF DataItem. rows x cols, cols = 0 for a 1D dataset.
std::string data_item(const std::string& h5_file, const std::string& dataset, int64_t rows,
                      int cols, const char* number_type, int precision) {
  std::ostringstream s;
  s << "<DataItem Dimensions=\"" << rows << (cols ? " " + std::to_string(cols) : "")
    << "\" NumberType=\"" << number_type << "\" Precision=\"" << precision << "\" Format=\"HDF\">"
    << escape_xml(h5_file) << ":" << dataset << "</DataItem>";
  return s.str();
}

// gmsh orders the Tet10 edge nodes (0,1) (1,2) (2,0) (3,0) (3,2) (3,1), VTK (and so XDMF's
// Tetrahedron_10 in ParaView) (0,1) (1,2) (2,0) (0,3) (1,3) (2,3): nodes 8 and 9 swap.
std::vector<int64_t> vtk_topology(const OutputLayout& layout) {
  std::vector<int64_t> topology = layout.topology;
  if (layout.order == 2)
    for (int64_t e = 0; e < layout.my_tets(); ++e)
      std::swap(topology[10 * e + 8], topology[10 * e + 9]);
  return topology;
}

// A group's name as an HDF5 dataset name and an XDMF attribute name: letters, digits, _, -
// and . kept, anything else (a / would make a path) replaced by _.
std::string dataset_name(const std::string& group) {
  std::string out = "group_";
  for (char c : group)
    out +=
        std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ? c : '_';
  return out;
}

// The names as a JSON list, the index -> name mapping kept beside an index field.
std::string json_list(const std::vector<std::string>& names) {
  return nlohmann::json(names).dump();
}

void require_size(const char* field, size_t size, int64_t expected) {
  if (static_cast<int64_t>(size) != expected)
    throw std::invalid_argument(std::string("XdmfWriter::write_step: ") + field + " has " +
                                std::to_string(size) + " values, expected " +
                                std::to_string(expected));
}

// The first non-finite entry of this rank's rows, named by its mesh node or tetrahedron
// ("" if none).
std::string first_non_finite(const char* field, const std::vector<double>& values,
                             const std::vector<int64_t>& ids, bool nodal, size_t step,
                             double time) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) continue;
    const int64_t row = nodal ? static_cast<int64_t>(i / 3) : static_cast<int64_t>(i);
    std::string where =
        std::string(field) + "[" + std::to_string(nodal ? 3 * ids[row] + i % 3 : ids[row]) + "]";
    if (nodal)
      where += " (node " + std::to_string(ids[row]) + ", " + "xyz"[i % 3] + ")";
    else
      where += " (tetrahedron " + std::to_string(ids[row]) + ")";
    return "output step " + std::to_string(step) + " (time " + number_text(time) + "): " + where +
           " is not finite (" + std::to_string(values[i]) + "); the step was not written";
  }
  return {};
}

// The same for a field of several values per tetrahedron.
std::string first_non_finite_cell(const char* field, const std::vector<double>& values, int per_tet,
                                  const std::vector<int64_t>& ids, size_t step, double time) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) continue;
    const int64_t tet = ids[i / per_tet];
    return "output step " + std::to_string(step) + " (time " + number_text(time) + "): " + field +
           "[" + std::to_string(per_tet * tet + static_cast<int64_t>(i % per_tet)) +
           "] (tetrahedron " + std::to_string(tet) + ") is not finite (" +
           std::to_string(values[i]) + "); the step was not written";
  }
  return {};
}

}  // namespace

std::string XdmfWriter::Impl::grid(const std::string& indent, int step) const {
  const std::string h5 = name + ".h5";  // relative: the folder moves on commit
  const std::string in = indent + "  ", in2 = indent + "    ";
  std::ostringstream x;
  x << indent << "<Grid Name=\"" << (step < 0 ? "mesh" : "step_" + std::to_string(step))
    << "\" GridType=\"Uniform\">\n";
  if (step >= 0) x << in << "<Time Value=\"" << number_text(time_value(step)) << "\"/>\n";
  x << in << "<Topology TopologyType=\"" << (nodes_per_tet == 4 ? "Tetrahedron" : "Tetrahedron_10")
    << "\" NumberOfElements=\"" << tets << "\" NodesPerElement=\"" << nodes_per_tet << "\">\n"
    << in2 << data_item(h5, "/mesh/topology", tets, nodes_per_tet, "Int", 8) << "\n"
    << in << "</Topology>\n"
    << in << "<Geometry GeometryType=\"XYZ\">\n"
    << in2 << data_item(h5, "/mesh/coordinates", nodes, 3, "Float", 8) << "\n"
    << in << "</Geometry>\n";
  auto attribute = [&](const char* field, const char* kind, const char* center, int64_t rows,
                       int cols, const char* number_type, int precision) {
    const std::string dataset = "/step_" + std::to_string(step) + "/" + field;
    x << in << "<Attribute Name=\"" << field << "\" AttributeType=\"" << kind << "\" Center=\""
      << center << "\">\n"
      << in2 << data_item(h5, dataset, rows, cols, number_type, precision) << "\n"
      << in << "</Attribute>\n";
  };
  // The physical groups on every grid, so that ParaView can threshold by them at any step.
  auto mesh_attribute = [&](const std::string& field, const char* center, int64_t rows) {
    x << in << "<Attribute Name=\"" << escape_xml(field) << "\" AttributeType=\"Scalar\" Center=\""
      << center << "\">\n"
      << in2 << data_item(h5, "/mesh/" + field, rows, 0, "Int", 4) << "\n"
      << in << "</Attribute>\n";
  };
  mesh_attribute("volume_group", "Cell", tets);
  for (const std::string& mask : mask_names) mesh_attribute(mask, "Node", nodes);
  if (step >= 0) {
    x << in << "<Information Name=\"time_kind\" Value=\"" << escape_xml(time_kinds[step])
      << "\"/>\n";
    attribute("displacement", "Vector", "Node", nodes, 3, "Float", 8);
    attribute("nodal_load", "Vector", "Node", nodes, 3, "Float", 8);
    if (has_pressure[step])
      attribute("cavity_pressure_load", "Vector", "Node", nodes, 3, "Float", 8);
    if (has_weight[step]) attribute("fluid_weight_load", "Vector", "Node", nodes, 3, "Float", 8);
    if (has_nodal_pressure[step]) attribute("pressure", "Scalar", "Node", nodes, 0, "Float", 8);
    for (const auto& [field, components] : node_fields[step])
      attribute(field.c_str(), components == 1 ? "Scalar" : "Vector", "Node", nodes,
                components == 1 ? 0 : components, "Float", 8);
    attribute("von_mises", "Scalar", "Cell", tets, 0, "Float", 8);
    if (has_tensors[step]) {
      // Full 3 x 3 tensors: XDMF's Tensor6 order (xx xy xz yy yz zz) is not VTK's symmetric
      // order (xx yy zz xy yz xz), and the readers differ in whether they convert it.
      attribute("stress", "Tensor", "Cell", tets, 9, "Float", 8);
      attribute("strain", "Tensor", "Cell", tets, 9, "Float", 8);
      attribute("principal_stress", "Vector", "Cell", tets, 3, "Float", 8);
      attribute("principal_strain", "Vector", "Cell", tets, 3, "Float", 8);
    }
    attribute("J", "Scalar", "Cell", tets, 0, "Float", 8);
    attribute("rank", "Scalar", "Cell", tets, 0, "Int", 4);
  }
  x << indent << "</Grid>\n";
  return x.str();
}

// ParaView orders steps by time and merges equal times: when the times are not
// increasing (a schedule that unloads), the step numbers stand in for them.
double XdmfWriter::Impl::time_value(int step) const {
  for (size_t k = 1; k < times.size(); ++k)
    if (!(times[k] > times[k - 1])) return step;
  return times[step];
}

void XdmfWriter::Impl::write_xdmf() const { write_file_atomically(xmf_path(), xdmf_text()); }

std::string XdmfWriter::Impl::xdmf_text() const {
  std::ostringstream x;
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n";
  if (times.empty()) {
    x << grid("    ", -1);  // the mesh alone, before the first step
  } else {
    x << "    <Grid Name=\"" << escape_xml(name)
      << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (size_t k = 0; k < times.size(); ++k) x << grid("      ", static_cast<int>(k));
    x << "    </Grid>\n";
  }
  x << "  </Domain>\n</Xdmf>\n";
  return x.str();
}

OutputLayout whole_layout(const Mesh& mesh) {
  OutputLayout l;
  l.order = mesh.order;
  l.nodes = mesh.num_nodes();
  l.tets = mesh.num_tets();
  l.x = mesh.x;
  l.topology = mesh.tets;
  l.node_ids.resize(l.nodes);
  l.tet_ids.resize(l.tets);
  for (int64_t n = 0; n < l.nodes; ++n) l.node_ids[n] = n;
  for (int64_t t = 0; t < l.tets; ++t) l.tet_ids[t] = t;
  l.volume_group = mesh.tet_volume;
  l.volume_names = mesh.volume_names;
  for (const auto& [name, members] : mesh.node_groups) {
    if (std::find(l.volume_names.begin(), l.volume_names.end(), name) != l.volume_names.end())
      continue;  // volume_group holds it
    OutputLayout::NodeGroup group{name, std::vector<int>(l.nodes, 0)};
    for (int64_t n : members) group.mask[n] = 1;
    l.node_groups.push_back(std::move(group));
  }
  return l;
}

XdmfWriter::XdmfWriter(const std::string& folder, const std::string& name, const Mesh& mesh)
    : XdmfWriter(MPI_COMM_NULL, folder, name, whole_layout(mesh)) {}

XdmfWriter::XdmfWriter(MPI_Comm comm, const std::string& folder, const std::string& name,
                       OutputLayout layout)
    : impl_(std::make_unique<Impl>()) {
  Impl& w = *impl_;
  w.comm = comm;
  if (comm != MPI_COMM_NULL) MPI_Comm_rank(comm, &w.rank);
  w.folder = folder;
  w.name = name;
  w.nodes_per_tet = layout.order == 1 ? 4 : 10;
  w.nodes = layout.nodes;
  w.tets = layout.tets;
  w.first_node = layout.first_node;
  w.first_tet = layout.first_tet;
  w.my_nodes = layout.my_nodes();
  w.my_tets = layout.my_tets();
  require_size("volume_group", layout.volume_group.size(), w.my_tets);
  const int64_t masks = static_cast<int64_t>(layout.node_groups.size());
  const int64_t bytes = w.nodes * (3 * 8 + 8 + 4 * masks) + w.tets * (w.nodes_per_tet * 8 + 8 + 4) +
                        Hdf5File::metadata_allowance(16 + 3 * masks);
  Hdf5File h5(w.h5_path(), Hdf5File::Mode::Create, comm, bytes);
  h5.create_group("/mesh");
  h5.write_rows("/mesh/coordinates", layout.x, w.nodes, 3, w.first_node);
  h5.set_attribute("/mesh/coordinates", "units", std::string("m"));
  h5.write_rows("/mesh/topology", vtk_topology(layout), w.tets, w.nodes_per_tet, w.first_tet);
  h5.write_rows("/mesh/node_ids", layout.node_ids, w.nodes, 0, w.first_node);
  h5.write_rows("/mesh/tet_ids", layout.tet_ids, w.tets, 0, w.first_tet);
  h5.write_rows("/mesh/volume_group", layout.volume_group, w.tets, 0, w.first_tet);
  h5.set_attribute("/mesh/volume_group", "names", json_list(layout.volume_names));
  std::vector<std::string> groups;
  for (const auto& group : layout.node_groups) {
    require_size(group.name.c_str(), group.mask.size(), w.my_nodes);
    const std::string dataset = "/mesh/" + dataset_name(group.name);
    if (std::find(w.mask_names.begin(), w.mask_names.end(), dataset_name(group.name)) !=
        w.mask_names.end())
      continue;  // two names that differ only in replaced characters: the first one is kept
    h5.write_rows(dataset, group.mask, w.nodes, 0, w.first_node);
    h5.set_attribute(dataset, "group", group.name);
    w.mask_names.push_back(dataset_name(group.name));
    groups.push_back(group.name);
  }
  h5.set_attribute("/mesh", "node_groups", json_list(groups));
  for (const char* index : {"topology", "node_ids", "tet_ids", "volume_group"})
    h5.set_attribute(std::string("/mesh/") + index, "units", std::string("1"));
  for (const std::string& mask : w.mask_names)
    h5.set_attribute("/mesh/" + mask, "units", std::string("1"));
  h5.close();
  w.node_ids = std::move(layout.node_ids);
  w.tet_ids = std::move(layout.tet_ids);
  // The mesh alone until the first step.
  write_together(comm, w.rank == 0, [&] { w.write_xdmf(); });
}

XdmfWriter::~XdmfWriter() = default;

void XdmfWriter::write_step(const StepFields& f) {
  Impl& w = *impl_;
  if (w.closed) throw std::logic_error("XdmfWriter::write_step after close");
  require_size("displacement", f.displacement.size(), 3 * w.my_nodes);
  require_size("nodal_load", f.nodal_load.size(), 3 * w.my_nodes);
  require_size("von_mises", f.von_mises.size(), w.my_tets);
  require_size("J", f.J.size(), w.my_tets);
  require_size("rank", f.rank.size(), w.my_tets);
  const bool pressure = !f.cavity_pressure_load.empty(), weight = !f.fluid_weight_load.empty();
  if (pressure) require_size("cavity_pressure_load", f.cavity_pressure_load.size(), 3 * w.my_nodes);
  if (weight) require_size("fluid_weight_load", f.fluid_weight_load.size(), 3 * w.my_nodes);
  const bool nodal_pressure = !f.pressure.empty();
  if (nodal_pressure) require_size("pressure", f.pressure.size(), w.my_nodes);
  for (const auto& field : f.node_fields)
    require_size(field.name.c_str(), field.values.size(), field.components * w.my_nodes);
  const bool tensors = !f.stress.empty();
  if (tensors) {
    require_size("stress", f.stress.size(), 9 * w.my_tets);
    require_size("strain", f.strain.size(), 9 * w.my_tets);
    require_size("principal_stress", f.principal_stress.size(), 3 * w.my_tets);
    require_size("principal_strain", f.principal_strain.size(), 3 * w.my_tets);
  }
  const size_t k = w.times.size();
  if (!std::isfinite(f.time))
    throw SolveError("output step " + std::to_string(k) + ": the time is not finite");
  std::string error = first_non_finite("displacement", f.displacement, w.node_ids, true, k, f.time);
  if (error.empty())
    error = first_non_finite("nodal_load", f.nodal_load, w.node_ids, true, k, f.time);
  if (error.empty())
    error = first_non_finite("von_mises", f.von_mises, w.tet_ids, false, k, f.time);
  if (error.empty()) error = first_non_finite("J", f.J, w.tet_ids, false, k, f.time);
  for (const auto& [field, values, per_tet] :
       {std::tuple<const char*, const std::vector<double>&, int>{"stress", f.stress, 9},
        {"strain", f.strain, 9},
        {"principal_stress", f.principal_stress, 3},
        {"principal_strain", f.principal_strain, 3}})
    if (error.empty()) error = first_non_finite_cell(field, values, per_tet, w.tet_ids, k, f.time);
  if (error.empty())
    error = first_non_finite("cavity_pressure_load", f.cavity_pressure_load, w.node_ids, true, k,
                             f.time);
  if (error.empty())
    error = first_non_finite("fluid_weight_load", f.fluid_weight_load, w.node_ids, true, k, f.time);
  for (size_t i = 0; i < f.pressure.size() && error.empty(); ++i)
    if (!std::isfinite(f.pressure[i]))
      error = "output step " + std::to_string(k) + " (time " + number_text(f.time) +
              "): pressure (node " + std::to_string(w.node_ids[i]) + ") is not finite (" +
              std::to_string(f.pressure[i]) + "); the step was not written";
  for (const auto& field : f.node_fields)
    for (size_t i = 0; i < field.values.size() && error.empty(); ++i)
      if (!std::isfinite(field.values[i]))
        error = "output step " + std::to_string(k) + " (time " + number_text(f.time) +
                "): " + field.name + " (node " + std::to_string(w.node_ids[i / field.components]) +
                ") is not finite (" + std::to_string(field.values[i]) +
                "); the step was not written";
  if (w.comm != MPI_COMM_NULL)
    throw_together<SolveError>(error, w.comm);
  else if (!error.empty())
    throw SolveError(error);

  const std::string step = "/step_" + std::to_string(k);
  const int64_t nodal_fields = 2 + pressure + weight;
  const int64_t cell_fields = 3 + 4 * tensors;
  int64_t extra_columns = 0;
  for (const auto& field : f.node_fields) extra_columns += field.components;
  const int64_t bytes =
      nodal_fields * w.nodes * 3 * 8 + nodal_pressure * w.nodes * 8 + extra_columns * w.nodes * 8 +
      w.tets * (8 + 8 + 4 + tensors * 24 * 8) +
      Hdf5File::metadata_allowance(
          3 + 2 * (nodal_fields + cell_fields + 1 + static_cast<int>(f.node_fields.size())),
          static_cast<int64_t>(k) + 1);
  // The step exists for readers once the .xmf names it. The new .xmf is written first (a full
  // disk then stops the step before the .h5 holds any of it) and put in place last: the .h5
  // never holds a step that the .xmf does not name, nor the .xmf one that the .h5 lacks.
  w.times.push_back(f.time);
  w.time_kinds.push_back(f.time_kind);
  w.has_pressure.push_back(pressure);
  w.has_weight.push_back(weight);
  w.has_tensors.push_back(tensors);
  w.has_nodal_pressure.push_back(nodal_pressure);
  w.node_fields.emplace_back();
  for (const auto& field : f.node_fields)
    w.node_fields.back().emplace_back(field.name, field.components);
  std::unique_ptr<StagedFile> xmf;  // rank 0's
  try {
    write_together(w.comm, w.rank == 0,
                   [&] { xmf = std::make_unique<StagedFile>(w.xmf_path(), w.xdmf_text()); });
    Hdf5File h5(w.h5_path(), Hdf5File::Mode::Append, w.comm, bytes);
    h5.create_group(step);
    h5.set_attribute(step, "time", f.time);
    h5.set_attribute(step, "time_kind", f.time_kind);
    auto nodal = [&](const char* field, const std::vector<double>& values, const char* units) {
      h5.write_rows(step + "/" + field, values, w.nodes, 3, w.first_node);
      h5.set_attribute(step + "/" + field, "units", std::string(units));
    };
    nodal("displacement", f.displacement, "m");
    nodal("nodal_load", f.nodal_load, "N");
    if (pressure) nodal("cavity_pressure_load", f.cavity_pressure_load, "N");
    if (weight) nodal("fluid_weight_load", f.fluid_weight_load, "N");
    if (nodal_pressure) {
      h5.write_rows(step + "/pressure", f.pressure, w.nodes, 0, w.first_node);
      h5.set_attribute(step + "/pressure", "units", std::string("Pa"));
    }
    for (const auto& field : f.node_fields) {
      h5.write_rows(step + "/" + field.name, field.values, w.nodes,
                    field.components == 1 ? 0 : field.components, w.first_node);
      h5.set_attribute(step + "/" + field.name, "units", field.units);
    }
    h5.write_rows(step + "/von_mises", f.von_mises, w.tets, 0, w.first_tet);
    h5.set_attribute(step + "/von_mises", "units", std::string("Pa"));
    if (tensors) {
      auto cells = [&](const char* field, const std::vector<double>& values, int cols,
                       const char* units) {
        h5.write_rows(step + "/" + field, values, w.tets, cols, w.first_tet);
        h5.set_attribute(step + "/" + field, "units", std::string(units));
      };
      cells("stress", f.stress, 9, "Pa");
      cells("strain", f.strain, 9, "1");
      cells("principal_stress", f.principal_stress, 3, "Pa");
      cells("principal_strain", f.principal_strain, 3, "1");
    }
    h5.write_rows(step + "/J", f.J, w.tets, 0, w.first_tet);
    h5.set_attribute(step + "/J", "units", std::string("1"));
    h5.write_rows(step + "/rank", f.rank, w.tets, 0, w.first_tet);
    h5.set_attribute(step + "/rank", "units", std::string("1"));
    h5.close();
    write_together(w.comm, w.rank == 0, [&] { xmf->commit(); });
  } catch (const SolveError& e) {
    w.times.pop_back();
    w.time_kinds.pop_back();
    w.has_pressure.pop_back();
    w.has_weight.pop_back();
    w.has_tensors.pop_back();
    w.has_nodal_pressure.pop_back();
    w.node_fields.pop_back();
    throw SolveError("output step " + std::to_string(k) + " (time " + number_text(f.time) +
                     ") not written: " + e.what());
  }
}

void XdmfWriter::close() {
  // The .xmf already names every step written (each step rewrites it): nothing is left to
  // write, and nothing can fail here on a full disk.
  impl_->closed = true;
}

std::string XdmfWriter::xdmf_file() const { return impl_->name + ".xmf"; }

std::string XdmfWriter::h5_file() const { return impl_->name + ".h5"; }

}  // namespace hs
