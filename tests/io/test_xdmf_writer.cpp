// XdmfWriter: the .h5 read back with the HDF5 C API and compared array by array; the .xmf
// parsed as XML and checked against the datasets it references; non-finite values refused;
// and, where /usr/bin/pvpython exists, opened with ParaView's three XDMF readers.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "../deck/temp_folder.hpp"
#include "common/error.hpp"
#include "file_size_limit.hpp"
#include "io/output.hpp"

namespace hs {
namespace {

using testing::TempFolder;

// Two tetrahedra sharing the face (1, 2, 3). At order 2, edge nodes are added at the edge
// midpoints in gmsh's order (0,1) (1,2) (2,0) (3,0) (3,2) (3,1), shared between the tets.
Mesh two_tets(int order) {
  Mesh m;
  m.x = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1.2, 0.9, 1.1};
  m.tets = {0, 1, 2, 3, 1, 2, 3, 4};
  m.tet_volume = {0, 1};
  m.volume_names = {"base", "cap"};
  // The volumes' nodes have no mask (volume_group holds them); a name with a space does.
  m.node_groups = {{"base", {0, 1, 2, 3}}, {"cap", {1, 2, 3, 4}}, {"tip face", {1, 4}}};
  if (order == 2) {
    const int gmsh_edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
    std::map<std::pair<int64_t, int64_t>, int64_t> midpoint;
    std::vector<int64_t> tets;
    for (int e = 0; e < 2; ++e) {
      const int64_t* v = &m.tets[4 * e];
      tets.insert(tets.end(), v, v + 4);
      for (const auto& edge : gmsh_edges) {
        const int64_t a = v[edge[0]], b = v[edge[1]];
        const auto key = std::minmax(a, b);
        if (!midpoint.count(key)) {
          midpoint[key] = m.num_nodes();
          for (int d = 0; d < 3; ++d) m.x.push_back((m.x[3 * a + d] + m.x[3 * b + d]) / 2);
        }
        tets.push_back(midpoint[key]);
      }
    }
    m.order = 2;
    m.tets = tets;
  }
  return m;
}

// Distinct, non-trivial values per step.
StepFields fields(const Mesh& mesh, int step, double time) {
  StepFields f;
  f.time = time;
  for (int64_t i = 0; i < 3 * mesh.num_nodes(); ++i) {
    f.displacement.push_back(std::sin(0.7 * i + step) * 1e-3);
    f.nodal_load.push_back(std::cos(0.3 * i - step) * 1e4);
    if (step == 1) {  // a step with cavities: the load's parts
      f.cavity_pressure_load.push_back(std::sin(0.2 * i) * 1e3);
      f.fluid_weight_load.push_back(-0.5 * i);
    }
  }
  for (int64_t e = 0; e < mesh.num_tets(); ++e) {
    f.von_mises.push_back(1e5 * (e + 1) + step);
    f.J.push_back(1 - 0.01 * (e + step));
    f.rank.push_back(static_cast<int>((e + step) % 2));
    if (step == 1) {  // a step with the tensors (9 and 3 per tetrahedron)
      for (int k = 0; k < 9; ++k) {
        f.stress.push_back(1e4 * (e + 1) * (k + 1) - step);
        f.strain.push_back(1e-3 * (k - 4) + e);
      }
      for (int k = 0; k < 3; ++k) {
        f.principal_stress.push_back(1e5 * (3 - k) + e);
        f.principal_strain.push_back(0.1 * (3 - k) - e);
      }
    }
  }
  return f;
}

// ---- Reading back with the HDF5 C API ----

struct Dataset {
  std::vector<hsize_t> dims;
  H5T_class_t type_class = H5T_NO_CLASS;
  size_t type_size = 0;
  std::vector<double> values;  // converted by HDF5 to double (exact for the int data here)
};

// nullopt-like: dims empty when the dataset does not exist.
Dataset read_dataset(const std::string& file, const std::string& name) {
  Dataset d;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // a missing dataset is an answer, not noise
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return d;
  const hid_t set = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  if (set >= 0) {
    const hid_t space = H5Dget_space(set), type = H5Dget_type(set);
    d.dims.resize(H5Sget_simple_extent_ndims(space));
    H5Sget_simple_extent_dims(space, d.dims.data(), nullptr);
    d.type_class = H5Tget_class(type);
    d.type_size = H5Tget_size(type);
    d.values.resize(H5Sget_simple_extent_npoints(space));
    H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.values.data());
    H5Tclose(type);
    H5Sclose(space);
    H5Dclose(set);
  }
  H5Fclose(f);
  return d;
}

std::vector<int64_t> read_int64(const std::string& file, const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t set = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t space = H5Dget_space(set);
  std::vector<int64_t> values(H5Sget_simple_extent_npoints(space));
  H5Dread(set, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Sclose(space);
  H5Dclose(set);
  H5Fclose(f);
  return values;
}

// A fixed-length string attribute ("" if there is none).
std::string read_text_attribute(const std::string& file, const std::string& object,
                                const std::string& name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  std::string value;
  if (H5Aexists_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT) > 0) {
    const hid_t a = H5Aopen_by_name(f, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    const hid_t type = H5Aget_type(a);
    value.assign(H5Tget_size(type), '\0');
    H5Aread(a, type, value.data());
    H5Tclose(type);
    H5Aclose(a);
  }
  H5Fclose(f);
  return value.substr(0, value.find('\0'));
}

double read_time(const std::string& file, const std::string& group) {
  double t = NAN;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t a = H5Aopen_by_name(f, group.c_str(), "time", H5P_DEFAULT, H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_DOUBLE, &t);
  H5Aclose(a);
  H5Fclose(f);
  return t;
}

template <class T>
std::vector<double> as_doubles(const std::vector<T>& v) {
  return std::vector<double>(v.begin(), v.end());
}

// ---- A minimal XML reader for the subset the writer produces ----

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;
  std::string text;
  int parent = -1;  // index of the enclosing element
};

// Throws std::runtime_error unless the document is well-formed: one root, every tag
// closed by its own name, attributes as name="value".
std::vector<XmlElement> parse_xml(const std::string& xml) {
  std::vector<XmlElement> elements;
  std::vector<int> open;
  int roots = 0;
  size_t pos = 0;
  auto blank = [](const std::string& s) {
    return s.find_first_not_of(" \t\r\n") == std::string::npos;
  };
  static const std::regex attribute("\\s*([A-Za-z_][\\w:.-]*)=\"([^\"<]*)\"");
  for (size_t lt; (lt = xml.find('<', pos)) != std::string::npos;) {
    const std::string text = xml.substr(pos, lt - pos);
    if (open.empty() && !blank(text)) throw std::runtime_error("text outside the root: " + text);
    if (!open.empty()) elements[open.back()].text += text;
    const size_t gt = xml.find('>', lt);
    if (gt == std::string::npos) throw std::runtime_error("unterminated tag");
    std::string tag = xml.substr(lt + 1, gt - lt - 1);
    pos = gt + 1;
    if (tag.front() == '?') {
      if (tag.back() != '?' || !elements.empty()) throw std::runtime_error("bad declaration");
      continue;
    }
    if (tag.front() == '/') {
      if (open.empty() || elements[open.back()].name != tag.substr(1))
        throw std::runtime_error("</" + tag.substr(1) + "> closes nothing open");
      open.pop_back();
      continue;
    }
    const bool self_closing = tag.back() == '/';
    if (self_closing) tag.pop_back();
    XmlElement e;
    const size_t name_end = std::min(tag.find_first_of(" \t\r\n"), tag.size());
    e.name = tag.substr(0, name_end);
    std::string rest = tag.substr(name_end);
    for (std::smatch m; std::regex_search(rest, m, attribute) && m.position(0) == 0;
         rest = m.suffix()) {
      if (!e.attributes.emplace(m[1], m[2]).second) throw std::runtime_error("repeated attribute");
    }
    if (!blank(rest)) throw std::runtime_error("malformed attributes in <" + tag + ">");
    e.parent = open.empty() ? -1 : open.back();
    if (open.empty()) ++roots;
    elements.push_back(e);
    if (!self_closing) open.push_back(static_cast<int>(elements.size()) - 1);
  }
  if (!open.empty()) throw std::runtime_error("<" + elements[open.back()].name + "> never closed");
  if (roots != 1 || !blank(xml.substr(pos))) throw std::runtime_error("not exactly one root");
  return elements;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The .xmf: a Temporal collection of one Uniform grid per step, each with its own Time;
// every DataItem names a dataset of the .h5 with the right dimensions and number type.
void check_xmf(const std::string& folder, const std::string& name, const Mesh& mesh,
               const std::vector<double>& times) {
  const auto elements = parse_xml(read_text(folder + "/" + name + ".xmf"));
  ASSERT_EQ(elements[0].name, "Xdmf");
  int collection = -1, grids = 0, items = 0;
  for (size_t i = 0; i < elements.size(); ++i) {
    const XmlElement& e = elements[i];
    if (e.name == "Grid" && e.attributes.count("CollectionType")) {
      EXPECT_EQ(e.attributes.at("CollectionType"), "Temporal");
      collection = static_cast<int>(i);
    }
    if (e.name == "Time") {
      EXPECT_EQ(e.attributes.count("TimeType"), 0u) << "ParaView's Xdmf3 readers abort on it";
      ASSERT_GE(e.parent, 0);
      EXPECT_EQ(elements[e.parent].attributes.at("GridType"), "Uniform");
    }
    if (e.name == "Grid" && e.attributes.at("GridType") == "Uniform") {
      EXPECT_EQ(e.parent, collection);
      EXPECT_EQ(e.attributes.at("Name"), "step_" + std::to_string(grids));
      int time_children = 0;
      for (const auto& c : elements) {
        if (c.parent != static_cast<int>(i) || c.name != "Time") continue;
        ++time_children;
        EXPECT_EQ(std::stod(c.attributes.at("Value")), times.at(grids));
      }
      EXPECT_EQ(time_children, 1);
      ++grids;
    }
    if (e.name == "Topology") {
      EXPECT_EQ(e.attributes.at("TopologyType"),
                mesh.order == 1 ? "Tetrahedron" : "Tetrahedron_10");
      EXPECT_EQ(e.attributes.at("NumberOfElements"), std::to_string(mesh.num_tets()));
    }
    if (e.name == "DataItem") {
      ++items;
      EXPECT_EQ(e.attributes.at("Format"), "HDF");
      const size_t colon = e.text.find(':');
      ASSERT_NE(colon, std::string::npos) << e.text;
      EXPECT_EQ(e.text.substr(0, colon), name + ".h5");
      const Dataset d =
          read_dataset(folder + "/" + e.text.substr(0, colon), e.text.substr(colon + 1));
      ASSERT_FALSE(d.dims.empty()) << "no dataset " << e.text;
      std::string dims;
      for (hsize_t n : d.dims) dims += (dims.empty() ? "" : " ") + std::to_string(n);
      EXPECT_EQ(e.attributes.at("Dimensions"), dims) << e.text;
      EXPECT_EQ(e.attributes.at("NumberType"), d.type_class == H5T_FLOAT ? "Float" : "Int");
      EXPECT_EQ(e.attributes.at("Precision"), std::to_string(d.type_size));
    }
  }
  EXPECT_GE(collection, 0);
  EXPECT_EQ(grids, static_cast<int>(times.size()));
  int loaded = 0, tensors = 0;  // steps with the load parts, with the tensors
  for (int k = 0; k < grids; ++k) {
    const std::string step = "/step_" + std::to_string(k);
    loaded +=
        !read_dataset(folder + "/" + name + ".h5", step + "/cavity_pressure_load").dims.empty();
    tensors += !read_dataset(folder + "/" + name + ".h5", step + "/stress").dims.empty();
  }
  // Topology, geometry, volume_group, the one node mask and five fields per step.
  EXPECT_EQ(items, 9 * grids + 2 * loaded + 4 * tensors);
  // The tensors as ParaView's 3 x 3 tensors, their principal values as 3 components.
  for (const auto& e : elements) {
    if (e.name != "Attribute") continue;
    const std::string& field = e.attributes.at("Name");
    if (field == "stress" || field == "strain")
      EXPECT_EQ(e.attributes.at("AttributeType"), "Tensor") << field;
    if (field.rfind("principal_", 0) == 0)
      EXPECT_EQ(e.attributes.at("AttributeType"), "Vector") << field;
    if (field == "stress" || field.rfind("principal_", 0) == 0)
      EXPECT_EQ(e.attributes.at("Center"), "Cell") << field;
  }
}

// ---- Tests ----

class XdmfWriterTest : public ::testing::TestWithParam<int> {
 protected:
  // Writes two steps of the mesh of the test's order; returns the mesh.
  Mesh write_two_steps() {
    const Mesh mesh = two_tets(GetParam());
    XdmfWriter writer(folder(), "case", mesh);
    writer.write_step(fields(mesh, 0, 0.5));
    check_xmf(folder(), "case", mesh, {0.5});  // rewritten after every step
    writer.write_step(fields(mesh, 1, 1.0));
    EXPECT_EQ(writer.xdmf_file(), "case.xmf");
    return mesh;
  }
  std::string folder() const { return tmp.path().string(); }
  std::string h5() const { return folder() + "/case.h5"; }
  TempFolder tmp;
};

TEST_P(XdmfWriterTest, Hdf5HoldsEveryArray) {
  const Mesh mesh = write_two_steps();
  const int64_t N = mesh.num_nodes(), E = mesh.num_tets(), npe = mesh.nodes_per_tet();
  const Dataset x = read_dataset(h5(), "/mesh/coordinates");
  EXPECT_EQ(x.dims, (std::vector<hsize_t>{hsize_t(N), 3}));
  EXPECT_EQ(x.values, mesh.x);
  const Dataset topology = read_dataset(h5(), "/mesh/topology");
  EXPECT_EQ(topology.dims, (std::vector<hsize_t>{hsize_t(E), hsize_t(npe)}));
  EXPECT_EQ(topology.type_class, H5T_INTEGER);
  EXPECT_EQ(topology.type_size, 8u);
  for (int step = 0; step < 2; ++step) {
    const std::string group = "/step_" + std::to_string(step);
    const StepFields f = fields(mesh, step, 0.5 * (step + 1));
    EXPECT_EQ(read_time(h5(), group), f.time);
    EXPECT_EQ(read_dataset(h5(), group + "/displacement").values, f.displacement);
    EXPECT_EQ(read_dataset(h5(), group + "/displacement").dims,
              (std::vector<hsize_t>{hsize_t(N), 3}));
    EXPECT_EQ(read_dataset(h5(), group + "/nodal_load").values, f.nodal_load);
    EXPECT_EQ(read_dataset(h5(), group + "/von_mises").values, f.von_mises);
    EXPECT_EQ(read_dataset(h5(), group + "/J").values, f.J);
    EXPECT_EQ(read_dataset(h5(), group + "/J").dims, (std::vector<hsize_t>{hsize_t(E)}));
    const Dataset rank = read_dataset(h5(), group + "/rank");
    EXPECT_EQ(rank.values, as_doubles(f.rank));
    EXPECT_EQ(rank.type_class, H5T_INTEGER);
  }
  EXPECT_TRUE(read_dataset(h5(), "/step_2/J").dims.empty());
  // The load parts only where the step has them.
  EXPECT_TRUE(read_dataset(h5(), "/step_0/cavity_pressure_load").dims.empty());
  EXPECT_TRUE(read_dataset(h5(), "/step_0/fluid_weight_load").dims.empty());
  const StepFields f = fields(mesh, 1, 1.0);
  EXPECT_EQ(read_dataset(h5(), "/step_1/cavity_pressure_load").values, f.cavity_pressure_load);
  EXPECT_EQ(read_dataset(h5(), "/step_1/fluid_weight_load").values, f.fluid_weight_load);
  // The tensors only where the step has them: E x 9 and E x 3, row by row.
  EXPECT_TRUE(read_dataset(h5(), "/step_0/stress").dims.empty());
  EXPECT_EQ(read_dataset(h5(), "/step_1/stress").values, f.stress);
  EXPECT_EQ(read_dataset(h5(), "/step_1/stress").dims, (std::vector<hsize_t>{hsize_t(E), 9}));
  EXPECT_EQ(read_dataset(h5(), "/step_1/strain").values, f.strain);
  EXPECT_EQ(read_dataset(h5(), "/step_1/principal_stress").values, f.principal_stress);
  EXPECT_EQ(read_dataset(h5(), "/step_1/principal_strain").dims,
            (std::vector<hsize_t>{hsize_t(E), 3}));
  EXPECT_EQ(read_dataset(h5(), "/step_1/principal_strain").values, f.principal_strain);
  // The physical groups, their names and every dataset's units.
  EXPECT_EQ(read_dataset(h5(), "/mesh/volume_group").values, (std::vector<double>{0, 1}));
  EXPECT_EQ(read_text_attribute(h5(), "/mesh/volume_group", "names"), "[\"base\",\"cap\"]");
  std::vector<double> tip(N, 0.0);
  tip[1] = tip[4] = 1;
  EXPECT_EQ(read_dataset(h5(), "/mesh/group_tip_face").values, tip);
  EXPECT_EQ(read_text_attribute(h5(), "/mesh/group_tip_face", "group"), "tip face");
  EXPECT_EQ(read_text_attribute(h5(), "/mesh", "node_groups"), "[\"tip face\"]");
  EXPECT_TRUE(read_dataset(h5(), "/mesh/group_base").dims.empty());
  EXPECT_EQ(read_text_attribute(h5(), "/step_1", "time_kind"), "load_factor");
  const std::map<std::string, std::string> units = {{"/mesh/coordinates", "m"},
                                                    {"/mesh/topology", "1"},
                                                    {"/mesh/volume_group", "1"},
                                                    {"/mesh/group_tip_face", "1"},
                                                    {"/step_1/displacement", "m"},
                                                    {"/step_1/nodal_load", "N"},
                                                    {"/step_1/cavity_pressure_load", "N"},
                                                    {"/step_1/fluid_weight_load", "N"},
                                                    {"/step_1/von_mises", "Pa"},
                                                    {"/step_1/stress", "Pa"},
                                                    {"/step_1/strain", "1"},
                                                    {"/step_1/principal_stress", "Pa"},
                                                    {"/step_1/principal_strain", "1"},
                                                    {"/step_1/J", "1"},
                                                    {"/step_1/rank", "1"}};
  for (const auto& [dataset, unit] : units)
    EXPECT_EQ(read_text_attribute(h5(), dataset, "units"), unit) << dataset;
}

TEST_P(XdmfWriterTest, TopologyIsInVtkNodeOrder) {
  const Mesh mesh = write_two_steps();
  const std::vector<int64_t> topology = read_int64(h5(), "/mesh/topology");
  const int npe = mesh.nodes_per_tet();
  ASSERT_EQ(topology.size(), mesh.tets.size());
  // VTK's quadratic tetra: node 4 + k is the midpoint of edge k (straight edges here).
  const int vtk_edges[6][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}};
  for (int64_t e = 0; e < mesh.num_tets(); ++e) {
    const int64_t* t = &topology[npe * e];
    for (int i = 0; i < 4; ++i) EXPECT_EQ(t[i], mesh.tets[npe * e + i]);  // vertices as given
    if (npe == 4) continue;
    for (int k = 0; k < 6; ++k)
      for (int d = 0; d < 3; ++d)
        EXPECT_DOUBLE_EQ(
            mesh.x[3 * t[4 + k] + d],
            (mesh.x[3 * t[vtk_edges[k][0]] + d] + mesh.x[3 * t[vtk_edges[k][1]] + d]) / 2)
            << "tet " << e << ", VTK edge " << k;
  }
}

TEST_P(XdmfWriterTest, XmfReferencesTheDatasets) {
  const Mesh mesh = write_two_steps();
  check_xmf(folder(), "case", mesh, {0.5, 1.0});
  EXPECT_FALSE(std::filesystem::exists(folder() + "/case.xmf.tmp"));
}

TEST_P(XdmfWriterTest, ParaViewReadersOpenTheFile) {
  const char* pvpython = "/usr/bin/pvpython";
  if (!std::filesystem::exists(pvpython)) GTEST_SKIP() << "no " << pvpython;
  const Mesh mesh = write_two_steps();
  const std::string command =
      std::string(pvpython) + " " + HYDROSOFT_SOURCE_DIR + "/postprocess/check_xdmf_paraview.py " +
      folder() + "/case.xmf --points " + std::to_string(mesh.num_nodes()) + " --cells " +
      std::to_string(mesh.num_tets()) + " --times 0.5,1 --straight-edges";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
}

TEST_P(XdmfWriterTest, RefusesNonFiniteValues) {
  const Mesh mesh = two_tets(GetParam());
  XdmfWriter writer(folder(), "case", mesh);
  writer.write_step(fields(mesh, 0, 0.5));
  auto message = [&](StepFields f) -> std::string {
    try {
      writer.write_step(f);
    } catch (const SolveError& e) {
      return e.what();
    }
    return "no error";
  };
  StepFields f = fields(mesh, 1, 1.0);
  f.displacement[7] = NAN;
  EXPECT_EQ(message(f).find("output step 1 (time 1): displacement[7] (node 2, y) is not finite"),
            0u)
      << message(f);
  f = fields(mesh, 1, 1.0);
  f.J[1] = INFINITY;
  EXPECT_NE(message(f).find("J[1] (tetrahedron 1) is not finite"), std::string::npos);
  f = fields(mesh, 1, 1.0);
  f.stress[9 + 4] = NAN;  // tetrahedron 1, yy
  EXPECT_NE(message(f).find("stress[13] (tetrahedron 1) is not finite"), std::string::npos)
      << message(f);
  f = fields(mesh, 1, 1.0);
  f.nodal_load.back() = -INFINITY;
  EXPECT_NE(message(f).find("nodal_load[" + std::to_string(3 * mesh.num_nodes() - 1) + "]"),
            std::string::npos);
  // Nothing of the refused steps was written: one step in the file and in the .xmf.
  EXPECT_TRUE(read_dataset(h5(), "/step_1/J").dims.empty());
  check_xmf(folder(), "case", mesh, {0.5});
  writer.write_step(fields(mesh, 1, 1.0));  // a finite step still goes in as step 1
  check_xmf(folder(), "case", mesh, {0.5, 1.0});
}

INSTANTIATE_TEST_SUITE_P(Order, XdmfWriterTest, ::testing::Values(1, 2),
                         [](const auto& info) { return "P" + std::to_string(info.param); });

TEST(XdmfWriter, NonIncreasingTimesBecomeStepNumbers) {
  TempFolder tmp;
  const Mesh mesh = two_tets(1);
  XdmfWriter writer(tmp.path().string(), "unload", mesh);
  for (double s : {0.5, 1.0, 0.5}) writer.write_step(fields(mesh, 0, s));
  writer.close();
  check_xmf(tmp.path().string(), "unload", mesh, {0, 1, 2});
  EXPECT_EQ(read_time(tmp.path().string() + "/unload.h5", "/step_2"), 0.5);  // the true value
}

TEST(XdmfWriter, MeshAloneBeforeTheFirstStep) {
  TempFolder tmp;
  const Mesh mesh = two_tets(2);
  XdmfWriter writer(tmp.path().string(), "empty", mesh);
  const auto elements = parse_xml(read_text(tmp.path().string() + "/empty.xmf"));
  int grids = 0, items = 0;
  for (const auto& e : elements) grids += e.name == "Grid", items += e.name == "DataItem";
  EXPECT_EQ(grids, 1);
  EXPECT_EQ(items, 4);  // topology, geometry, volume_group, group_tip_face
}

// A step that finds no room (a file size limit here, a full disk in a run) is refused before
// HDF5 writes anything: SolveError naming the step, the file and the reason, and the files as
// they were after the step before (the .h5 readable, the .xmf naming the steps written). Before:
// HDF5's error stack printed, std::runtime_error, and a file HDF5 could not close.
TEST(XdmfWriter, AStepThatFindsNoRoomLeavesTheStepsBefore) {
  TempFolder tmp;
  const Mesh mesh = two_tets(1);
  const std::string h5 = tmp.path().string() + "/full.h5";
  XdmfWriter writer(tmp.path().string(), "full", mesh);
  writer.write_step(fields(mesh, 0, 0.5));
  writer.write_step(fields(mesh, 1, 1.0));
  std::string message;
  {
    const testing::FileSizeLimit limit(std::filesystem::file_size(h5) + 100);
    try {
      writer.write_step(fields(mesh, 2, 1.5));
    } catch (const SolveError& e) {
      message = e.what();
    }
  }
  EXPECT_EQ(message.find("output step 2 (time 1.5) not written: " + h5 + ": no room for "), 0u)
      << message;
  EXPECT_NE(message.find(" KB more: File too large"), std::string::npos) << message;
  check_xmf(tmp.path().string(), "full", mesh, {0.5, 1.0});
  EXPECT_EQ(read_time(h5, "/step_1"), 1.0);
  const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  EXPECT_EQ(H5Lexists(file, "/step_2", H5P_DEFAULT), 0);
  H5Fclose(file);
  // With room again, the same step goes in as step 2.
  writer.write_step(fields(mesh, 2, 1.5));
  check_xmf(tmp.path().string(), "full", mesh, {0.5, 1.0, 1.5});
}

// The .xmf of a step that cannot be written (here its .tmp's name is taken by a folder; a full
// disk in a run) used to leave the step in the .h5 that no .xmf named: the .xmf is now written
// first, and the .h5 keeps only the steps the .xmf names.
TEST(XdmfWriter, AStepWhoseXmfCannotBeWrittenLeavesTheH5AsItWas) {
  TempFolder tmp;
  const Mesh mesh = two_tets(1);
  const std::string h5 = tmp.path().string() + "/full.h5";
  XdmfWriter writer(tmp.path().string(), "full", mesh);
  writer.write_step(fields(mesh, 0, 0.5));
  std::filesystem::create_directory(tmp.path() / "full.xmf.tmp");
  EXPECT_THROW(writer.write_step(fields(mesh, 1, 1.0)), SolveError);
  check_xmf(tmp.path().string(), "full", mesh, {0.5});
  const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  EXPECT_EQ(H5Lexists(file, "/step_1", H5P_DEFAULT), 0);
  H5Fclose(file);
  std::filesystem::remove(tmp.path() / "full.xmf.tmp");
  writer.write_step(fields(mesh, 1, 1.0));
  check_xmf(tmp.path().string(), "full", mesh, {0.5, 1.0});
}

}  // namespace
}  // namespace hs
