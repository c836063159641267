// XdmfWriter: one HDF5 file with the mesh once and the fields of every step, and an XDMF
// file that ParaView reads (docs/output.md). Layout of <name>.h5:
//   /mesh/coordinates  N x 3 float64      /mesh/topology  E x 4 or E x 10 int64 (VTK order)
//   /step_<k>/displacement, nodal_load  N x 3 float64;  von_mises, J  E float64;
//   /step_<k>/rank  E int32;  attribute /step_<k>/time.
// The .xmf is a Temporal collection of Uniform grids, each with its own <Time Value=.../>
// (ParaView 5.11's Xdmf3 readers abort on a <Time TimeType="List"> on the collection), all
// pointing at the same /mesh datasets. It is rewritten atomically after every step, so the
// staging folder of a run that is still going (or died) can be opened.
#include <charconv>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/error.hpp"
#include "io/atomic_file.hpp"
#include "io/hdf5_file.hpp"
#include "io/output.hpp"

namespace hs {

struct XdmfWriter::Impl {
  std::string folder, name;
  int nodes_per_tet = 4;
  int64_t nodes = 0, tets = 0;
  std::vector<double> times;  // of the steps written so far
  bool closed = false;

  std::string h5_path() const { return folder + "/" + name + ".h5"; }
  std::string xmf_path() const { return folder + "/" + name + ".xmf"; }
  // The XML of one Uniform grid: step k, or the mesh alone (step -1).
  std::string grid(const std::string& indent, int step) const;
  double time_value(int step) const;  // the <Time Value> of step k
  void write_xdmf() const;
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
std::vector<int64_t> vtk_topology(const Mesh& mesh) {
  std::vector<int64_t> topology = mesh.tets;
  if (mesh.order == 2)
    for (int64_t e = 0; e < mesh.num_tets(); ++e)
      std::swap(topology[10 * e + 8], topology[10 * e + 9]);
  return topology;
}

void require_size(const char* field, size_t size, int64_t expected) {
  if (static_cast<int64_t>(size) != expected)
    throw std::invalid_argument(std::string("XdmfWriter::write_step: ") + field + " has " +
                                std::to_string(size) + " values, expected " +
                                std::to_string(expected));
}

// Throws SolveError naming the first non-finite entry (and, for nodal fields, its node).
void require_finite(const char* field, const std::vector<double>& values, bool nodal, size_t step,
                    double time) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) continue;
    std::string where = std::string(field) + "[" + std::to_string(i) + "]";
    if (nodal)
      where += " (node " + std::to_string(i / 3) + ", " + "xyz"[i % 3] + ")";
    else
      where += " (tetrahedron " + std::to_string(i) + ")";
    throw SolveError("output step " + std::to_string(step) + " (time " + number_text(time) +
                     "): " + where + " is not finite (" + std::to_string(values[i]) +
                     "); the step was not written");
  }
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
  if (step >= 0) {
    attribute("displacement", "Vector", "Node", nodes, 3, "Float", 8);
    attribute("nodal_load", "Vector", "Node", nodes, 3, "Float", 8);
    attribute("von_mises", "Scalar", "Cell", tets, 0, "Float", 8);
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

void XdmfWriter::Impl::write_xdmf() const {
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
  write_file_atomically(xmf_path(), x.str());
}

XdmfWriter::XdmfWriter(const std::string& folder, const std::string& name, const Mesh& mesh)
    : impl_(std::make_unique<Impl>()) {
  impl_->folder = folder;
  impl_->name = name;
  impl_->nodes_per_tet = mesh.nodes_per_tet();
  impl_->nodes = mesh.num_nodes();
  impl_->tets = mesh.num_tets();
  Hdf5File h5(impl_->h5_path(), Hdf5File::Mode::Create);
  h5.create_group("/mesh");
  h5.write("/mesh/coordinates", mesh.x, impl_->nodes, 3);
  h5.write("/mesh/topology", vtk_topology(mesh), impl_->tets, impl_->nodes_per_tet);
  h5.close();
  impl_->write_xdmf();  // the mesh alone until the first step
}

XdmfWriter::~XdmfWriter() {
  try {
    close();
  } catch (...) {
    // Destructors must not throw; the file of the last step stays as it was.
  }
}

void XdmfWriter::write_step(const StepFields& f) {
  Impl& w = *impl_;
  if (w.closed) throw std::logic_error("XdmfWriter::write_step after close");
  require_size("displacement", f.displacement.size(), 3 * w.nodes);
  require_size("nodal_load", f.nodal_load.size(), 3 * w.nodes);
  require_size("von_mises", f.von_mises.size(), w.tets);
  require_size("J", f.J.size(), w.tets);
  require_size("rank", f.rank.size(), w.tets);
  const size_t k = w.times.size();
  if (!std::isfinite(f.time))
    throw SolveError("output step " + std::to_string(k) + ": the time is not finite");
  require_finite("displacement", f.displacement, true, k, f.time);
  require_finite("nodal_load", f.nodal_load, true, k, f.time);
  require_finite("von_mises", f.von_mises, false, k, f.time);
  require_finite("J", f.J, false, k, f.time);

  const std::string step = "/step_" + std::to_string(k);
  Hdf5File h5(w.h5_path(), Hdf5File::Mode::Append);
  h5.create_group(step);
  h5.set_attribute(step, "time", f.time);
  h5.write(step + "/displacement", f.displacement, w.nodes, 3);
  h5.write(step + "/nodal_load", f.nodal_load, w.nodes, 3);
  h5.write(step + "/von_mises", f.von_mises, w.tets, 0);
  h5.write(step + "/J", f.J, w.tets, 0);
  h5.write(step + "/rank", f.rank, w.tets, 0);
  h5.close();
  w.times.push_back(f.time);
  w.write_xdmf();
}

void XdmfWriter::close() {
  if (impl_->closed) return;
  impl_->write_xdmf();
  impl_->closed = true;
}

std::string XdmfWriter::xdmf_file() const { return impl_->name + ".xmf"; }

}  // namespace hs
