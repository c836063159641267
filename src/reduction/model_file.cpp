#include "reduction/model_file.hpp"

#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/error.hpp"
#include "io/hdf5_file.hpp"

namespace hs {
namespace {

const char* kFormat = "hydrosoft reduced model";
constexpr int kVersion = 1;

class Reader {
 public:
  explicit Reader(const std::string& path) : path_(path) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error))
      fail(error ? "cannot be examined: " + error.message() : "no such file");
    quiet_hdf5();
    file_.id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file_.id < 0) fail("not an HDF5 file");
  }
  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path_ + ": " + reason);
  }
  std::string text(const char* name) const {
    if (H5Aexists(file_.id, name) <= 0) return "";
    Hdf5Handle a{H5Aopen(file_.id, name, H5P_DEFAULT), H5Aclose};
    Hdf5Handle type{H5Aget_type(a.id), H5Tclose};
    std::string s(H5Tget_size(type.id), '\0');
    if (H5Tget_class(type.id) != H5T_STRING || H5Aread(a.id, type.id, s.data()) < 0) return "";
    return s;
  }
  // A dataset of `rows` x `cols` (cols 0: a list) of the given type, read whole.
  template <class T>
  std::vector<T> read(const char* name, hid_t type, hsize_t rows, hsize_t cols) const {
    if (H5Lexists(file_.id, name, H5P_DEFAULT) <= 0) fail(std::string("no ") + name);
    Hdf5Handle set{H5Dopen2(file_.id, name, H5P_DEFAULT), H5Dclose};
    Hdf5Handle space{H5Dget_space(set.id), H5Sclose};
    hsize_t dims[2] = {0, 0};
    const int ndims = H5Sget_simple_extent_ndims(space.id);
    if (ndims != (cols ? 2 : 1)) fail(std::string(name) + ": not the expected shape");
    H5Sget_simple_extent_dims(space.id, dims, nullptr);
    if (dims[0] != rows || (cols && dims[1] != cols))
      fail(std::string(name) + ": " + std::to_string(dims[0]) +
           (cols ? " x " + std::to_string(dims[1]) : "") + " values where the model says " +
           std::to_string(rows) + (cols ? " x " + std::to_string(cols) : ""));
    std::vector<T> out(rows * (cols ? cols : 1));
    if (!out.empty() && H5Dread(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
      fail(std::string(name) + ": cannot be read");
    return out;
  }

 private:
  std::string path_;
  Hdf5Handle file_{-1, H5Fclose};
};

std::vector<double> row_major(const Eigen::MatrixXd& a) {
  std::vector<double> v(a.size());
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j) v[i * a.cols() + j] = a(i, j);
  return v;
}

Eigen::MatrixXd from_row_major(const std::vector<double>& v, Eigen::Index rows, Eigen::Index cols) {
  Eigen::MatrixXd a(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) a(i, j) = v[i * cols + j];
  return a;
}

}  // namespace

double coordinate_checksum(const std::vector<double>& x) {
  double sum = 0;
  for (size_t n = 0; n < x.size() / 3; ++n)
    sum += static_cast<double>(n % 97 + 1) * (x[3 * n] + 2 * x[3 * n + 1] + 3 * x[3 * n + 2]);
  return sum;
}

void write_reduced_model(const std::string& path, const ReducedModel& m) {
  nlohmann::json info = {{"nodes", m.nodes},
                         {"tets", m.tets},
                         {"order", m.order},
                         {"coordinate_checksum", m.coordinate_checksum},
                         {"physics", m.physics},
                         {"deck", m.deck},
                         {"actuators", m.actuators},
                         {"lower", m.lower},
                         {"upper", m.upper},
                         {"modes", m.basis.cols()},
                         {"elements", m.elements.size()},
                         {"patches", m.patches.size()},
                         {"training_samples", m.training_states.rows()},
                         {"report", m.report}};
  const std::string tmp = path + ".tmp";
  const size_t rows = static_cast<size_t>(m.basis.rows()), k = static_cast<size_t>(m.basis.cols());
  const std::vector<double> basis = row_major(m.basis);
  {
    Hdf5File h5(tmp, Hdf5File::Mode::CreateLargeAttributes);
    h5.set_attribute("/", "format", std::string(kFormat));
    h5.set_attribute("/", "version", kVersion);
    h5.set_attribute("/", "model", info.dump());
    h5.write("/basis", basis, rows, k);
    h5.write("/elements", m.elements, m.elements.size(), 0);
    h5.write("/weights", m.weights, m.weights.size(), 0);
    if (!m.patches.empty()) {
      h5.write("/patches", m.patches, m.patches.size(), 0);
      h5.write("/patch_weights", m.patch_weights, m.patch_weights.size(), 0);
    }
    h5.write("/training_actuations", row_major(m.training_actuations), m.training_actuations.rows(),
             m.training_actuations.cols());
    h5.write("/training_states", row_major(m.training_states), m.training_states.rows(),
             m.training_states.cols());
    h5.close();
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw SolveError(path + ": the reduced model cannot be put in place");
  }
}

ReducedModel read_reduced_model(const std::string& path) {
  const Reader r(path);
  if (r.text("format") != kFormat) r.fail("not a hydrosoft reduced model");
  nlohmann::json info;
  ReducedModel m;
  int64_t k = 0, elements = 0, patches = 0, samples = 0;
  try {
    info = nlohmann::json::parse(r.text("model"));
    m.nodes = info.at("nodes");
    m.tets = info.at("tets");
    m.order = info.at("order");
    m.coordinate_checksum = info.at("coordinate_checksum");
    m.physics = info.at("physics");
    m.deck = info.at("deck");
    m.actuators = info.at("actuators").get<std::vector<std::string>>();
    m.lower = info.at("lower").get<std::vector<double>>();
    m.upper = info.at("upper").get<std::vector<double>>();
    k = info.at("modes");
    elements = info.at("elements");
    patches = info.value("patches", int64_t{0});
    samples = info.at("training_samples");
    m.report = info.at("report");
  } catch (const std::exception&) {
    r.fail("its model attribute is not the JSON a reduced model writes");
  }
  if (m.nodes < 4 || m.tets < 1 || elements < 0 || elements > m.tets || patches < 0 ||
      patches > m.nodes || elements + patches < 1 || samples < 1 || samples > 1000000 ||
      (m.order != 1 && m.order != 2) || k < 1 || k > 10000 || m.actuators.empty() ||
      m.lower.size() != m.actuators.size() || m.upper.size() != m.actuators.size())
    r.fail("its model attribute holds sizes no model has");
  const hsize_t rows = 3 * static_cast<hsize_t>(m.nodes);
  const std::vector<double> basis = r.read<double>("/basis", H5T_NATIVE_DOUBLE, rows, k);
  m.elements = r.read<int64_t>("/elements", H5T_NATIVE_INT64, elements, 0);
  m.weights = r.read<double>("/weights", H5T_NATIVE_DOUBLE, elements, 0);
  if (patches > 0) {
    m.patches = r.read<int64_t>("/patches", H5T_NATIVE_INT64, patches, 0);
    m.patch_weights = r.read<double>("/patch_weights", H5T_NATIVE_DOUBLE, patches, 0);
  }
  m.basis = from_row_major(basis, rows, k);
  if (!m.basis.allFinite()) r.fail("/basis holds a value that is not finite");
  const hsize_t actuators = m.actuators.size();
  m.training_actuations =
      from_row_major(r.read<double>("/training_actuations", H5T_NATIVE_DOUBLE, samples, actuators),
                     samples, actuators);
  m.training_states =
      from_row_major(r.read<double>("/training_states", H5T_NATIVE_DOUBLE, samples, k), samples, k);
  if (!m.training_actuations.allFinite() || !m.training_states.allFinite())
    r.fail("a training sample holds a value that is not finite");
  for (size_t e = 0; e < m.elements.size(); ++e) {
    if (m.elements[e] < 0 || m.elements[e] >= m.tets)
      r.fail("/elements: " + std::to_string(m.elements[e]) + " is not a tetrahedron of the mesh");
    if (!(std::isfinite(m.weights[e]) && m.weights[e] > 0))
      r.fail("/weights: the weight of element " + std::to_string(m.elements[e]) +
             " is not a positive number");
  }
  for (size_t p = 0; p < m.patches.size(); ++p) {
    if (m.patches[p] < 0 || m.patches[p] >= m.nodes)
      r.fail("/patches: " + std::to_string(m.patches[p]) + " is not a node of the mesh");
    if (!(std::isfinite(m.patch_weights[p]) && m.patch_weights[p] > 0))
      r.fail("/patch_weights: the weight of node " + std::to_string(m.patches[p]) +
             "'s patch is not a positive number");
  }
  for (size_t a = 0; a < m.lower.size(); ++a)
    if (!(std::isfinite(m.lower[a]) && std::isfinite(m.upper[a]) && m.lower[a] <= m.upper[a]))
      r.fail("the training envelope of actuator '" + m.actuators[a] + "' is not a range");
  return m;
}

}  // namespace hs
