// load_mesh: file checks, the gmsh session, meshing of .geo sources with deck parameters.
// The model -> Mesh step is in gmsh_model.cpp, the broadcast in mesh_broadcast.cpp.
#include "mesh/gmsh_io.hpp"

#include <gmsh.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "common/error.hpp"
#include "mesh/geo_guard.hpp"
#include "mesh/gmsh_model.hpp"
#include "mesh/msh_prescan.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;

// One gmsh session per load, quiet (errors reach the user through InputError), single
// threaded (reproducible meshes), finalised on every way out.
class GmshSession {
 public:
  GmshSession() {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.Verbosity", 1);  // errors only
    gmsh::option::setNumber("General.NumThreads", 1);
    // Never a question on standard input (gmsh asks whether to go on with "a very large
    // mesh" and reads the answer there): the input may be the run's control targets.
    gmsh::option::setNumber("General.NoPopup", 1);
  }
  ~GmshSession() { gmsh::finalize(); }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

std::ifstream open_input(const std::string& file) {
  std::ifstream in(file);
  if (!in || fs::is_directory(file))
    throw InputError(file + ": cannot open the mesh file (missing or unreadable)");
  return in;
}

std::string read_text(const std::string& file) {
  std::ifstream in = open_input(file);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

// Whether `name` occurs in `text` as a whole word (a guard against misspelt parameters).
bool mentions(const std::string& text, const std::string& name) {
  auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
    const bool left = at == 0 || !word_char(text[at - 1]);
    const size_t end = at + name.size();
    if (left && (end == text.size() || !word_char(text[end]))) return true;
  }
  return false;
}

// A .geo that defines the deck's parameters, includes the source, and checks that the
// source did not overwrite them. Parameters must be declared in the source with
// DefineConstant[name = default], which keeps a value defined before it; a plain
// assignment would silently replace it, hence the check. The text lives in an anonymous
// in-memory file (memfd) that gmsh opens as /proc/self/fd/N: nothing is written to disk, so
// nothing is left behind even when gmsh ends the process (a .geo's Exit) or it is killed.
class ParameterWrapper {
 public:
  ParameterWrapper(const std::string& file, const std::map<std::string, double>& parameters) {
    const std::string text = wrapper_text(file, parameters);
    fd_ = memfd_create("hydrosoft_mesh.geo", MFD_CLOEXEC);
    if (fd_ < 0) throw InputError(file + ": cannot create the in-memory .geo for its parameters");
    for (size_t done = 0; done < text.size();) {
      const ssize_t n = write(fd_, text.data() + done, text.size() - done);
      if (n <= 0) {
        close(fd_);
        throw InputError(file + ": cannot write the in-memory .geo for its parameters");
      }
      done += static_cast<size_t>(n);
    }
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  ~ParameterWrapper() { close(fd_); }
  ParameterWrapper(const ParameterWrapper&) = delete;
  ParameterWrapper& operator=(const ParameterWrapper&) = delete;
  const std::string& path() const { return path_; }

 private:
  static std::string wrapper_text(const std::string& file,
                                  const std::map<std::string, double>& parameters) {
    const std::string source = read_text(file);
    const std::string absolute = fs::absolute(file).lexically_normal().string();
    if (absolute.find('"') != std::string::npos)
      throw InputError(file + ": a .geo path with a double quote cannot be included");
    std::ostringstream geo;
    geo.precision(17);
    for (const auto& [name, value] : parameters) {
      const std::string where = file + ": mesh parameter '" + name + "'";
      if (!is_identifier(name)) throw InputError(where + " is not a .geo identifier");
      if (!std::isfinite(value)) throw InputError(where + " is not a finite number");
      if (!mentions(source, name)) throw InputError(where + " does not occur in the file");
      geo << name << " = " << value << ";\n";
    }
    geo << "Include \"" << absolute << "\";\n";
    for (const auto& [name, value] : parameters)
      geo << "If (" << name << " != " << value << ")\n  Error(\"mesh parameter '" << name
          << "' is overwritten by the .geo file: declare it with DefineConstant\");\nEndIf\n";
    return geo.str();
  }

  int fd_ = -1;
  std::string path_;
};

// mesh.max_elements counts tetrahedra after cfg.refine uniform refinements (8 each).
int64_t tets_after_refine(const MeshConfig& cfg, double tets) {
  const double after = tets * std::pow(8.0, cfg.refine);
  return after >= 9e18 ? INT64_MAX : static_cast<int64_t>(after);
}

[[noreturn]] void refuse_size(const MeshConfig& cfg, const std::string& what) {
  throw InputError(cfg.file + ": mesh.max_elements: " + what + ", above the limit of " +
                   std::to_string(cfg.max_elements) +
                   " tetrahedra (check mesh.parameters, or raise mesh.max_elements)");
}

std::string count_text(double n) {
  std::ostringstream s;
  s.precision(3);
  s << n;
  return s.str();
}

// Elements of dimension `dim` of gmsh's current model, of any type.
int64_t element_count(int dim) {
  std::vector<int> types;
  gmsh::model::mesh::getElementTypes(types, dim);
  int64_t count = 0;
  for (int type : types) {
    std::vector<size_t> tags, nodes;
    gmsh::model::mesh::getElementsByType(type, tags, nodes);
    count += static_cast<int64_t>(tags.size());
  }
  return count;
}

// The total length of the model's curves, from below: polylines through points on each.
double curve_length() {
  gmsh::vectorpair curves;
  gmsh::model::getEntities(curves, 1);
  double length = 0;
  for (const auto& [dim, tag] : curves) {
    std::vector<double> lo, hi, coords;
    gmsh::model::getParametrizationBounds(dim, tag, lo, hi);
    if (lo.empty() || hi.empty()) continue;
    std::vector<double> u(33);
    for (size_t k = 0; k < u.size(); ++k) u[k] = lo[0] + (hi[0] - lo[0]) * k / (u.size() - 1);
    gmsh::model::getValue(dim, tag, u, coords);
    for (size_t k = 3; k + 2 < coords.size(); k += 3)
      length += std::hypot(coords[k] - coords[k - 3], coords[k + 1] - coords[k - 2],
                           coords[k + 2] - coords[k - 1]);
  }
  return length;
}

// The total area (dim 2) or volume (dim 3) of an OpenCASCADE model; 0 for gmsh's own kernel,
// which cannot say.
double occ_measure(int dim) {
  gmsh::vectorpair entities;
  gmsh::model::getEntities(entities, dim);
  double total = 0;
  for (const auto& [d, tag] : entities) {
    try {
      double mass = 0;
      gmsh::model::occ::getMass(d, tag, mass);
      total += std::abs(mass);
    } catch (...) {  // not an OpenCASCADE entity
      return 0;
    }
  }
  return total;
}

// Before meshing: a lower bound on the tetrahedra of the model, from the largest element size
// h its options allow (Mesh.MeshSizeMax, or MeshSizeMin if larger, times MeshSizeFactor when
// above 1). gmsh accepts edges up to about 1.4 h, so counting with edges e = 1.5 h: the curves
// need length / e segments (each an edge of a tetrahedron, which has 6), the surfaces
// area / (sqrt 3 e^2 / 4) triangles (each a face of a tetrahedron, which has 4), the volumes
// volume / (e^3 / (6 sqrt 2)) tetrahedra. On every .geo of meshes/ this bound lies 2 to 5
// times below the tetrahedra gmsh makes. Huge mesh.parameters (a length of 1e9 at a size of
// 0.025) are refused here, before gmsh meshes (and exhausts the memory or fails).
void check_size_estimate(const MeshConfig& cfg) {
  double size_max = 0, size_min = 0, factor = 1;
  gmsh::option::getNumber("Mesh.MeshSizeMax", size_max);
  gmsh::option::getNumber("Mesh.MeshSizeMin", size_min);
  gmsh::option::getNumber("Mesh.MeshSizeFactor", factor);
  const double h = std::max(size_max, size_min) * std::max(factor, 1.0), e = 1.5 * h;
  if (!(e > 0) || !std::isfinite(e)) return;
  const double length = curve_length(), area = occ_measure(2), volume = occ_measure(3);
  const double by_curves = length / e / 6;
  const double by_surfaces = area / (std::sqrt(3.0) / 4 * e * e) / 4;
  const double by_volume = volume / (e * e * e / (6 * std::sqrt(2.0)));
  const double bound = std::max({by_curves, by_surfaces, by_volume});
  if (tets_after_refine(cfg, bound) > cfg.max_elements)
    refuse_size(
        cfg, "meshing would make at least " + count_text(bound) + " tetrahedra (curves " +
                 count_text(length) + " m long, surfaces " + count_text(area) + " m^2, volume " +
                 count_text(volume) + " m^3, at a mesh size of at most " + count_text(h) + " m)" +
                 (cfg.refine > 0 ? " before " + std::to_string(cfg.refine) + " refinements" : ""));
}

// Refuses `tets` tetrahedra (before refinement) above the limit.
void check_tet_count(const MeshConfig& cfg, double tets, const std::string& what) {
  const int64_t after = tets_after_refine(cfg, tets);
  if (after > cfg.max_elements)
    refuse_size(cfg,
                what + (cfg.refine > 0 ? ", " + count_text(static_cast<double>(after)) + " after " +
                                             std::to_string(cfg.refine) + " refinements"
                                       : ""));
}

// gmsh's meshers run inside OpenMP regions, which an exception cannot leave: a gmsh error
// raised there (General.AbortOnError 2 throws it) ends the process through std::terminate,
// before any handler of ours, with no word of what went wrong (a 10 km cantilever of 5 cm
// section did). Letting gmsh go on after the error instead (AbortOnError 1) kept that
// cantilever meshing in vain for more than 20 minutes. So while gmsh meshes, the terminate
// handler reports gmsh's error as an input error would be reported and ends the run at once:
// every rank, through MPI_Abort, when MPI runs.
class GmshErrorReport {
 public:
  explicit GmshErrorReport(const std::string& file) {
    file_ = file;
    previous_ = std::set_terminate(&report);
  }
  ~GmshErrorReport() { std::set_terminate(previous_); }
  GmshErrorReport(const GmshErrorReport&) = delete;
  GmshErrorReport& operator=(const GmshErrorReport&) = delete;

 private:
  [[noreturn]] static void report() {
    std::string what = "an unknown error";
    if (const std::exception_ptr error = std::current_exception()) {
      try {
        std::rethrow_exception(error);
      } catch (const std::string& text) {  // gmsh 4.8 throws its message as a string
        what = text;
      } catch (const std::exception& e) {
        what = e.what();
      } catch (...) {
      }
    }
    std::cerr << "hydrosoft: error: " << file_ << ": gmsh: " << what
              << " (raised inside gmsh's parallel mesher, which cannot hand it on: the run "
                 "stops here)"
              << std::endl;
    int initialized = 0, finalized = 0;
    MPI_Initialized(&initialized);
    MPI_Finalized(&finalized);
    if (initialized && !finalized) MPI_Abort(MPI_COMM_WORLD, 2);
    std::_Exit(2);
  }

  static inline std::string file_;
  std::terminate_handler previous_ = nullptr;
};

// The order of the tetrahedra of the current model: 1 or 2, 0 when it has none, -1 when
// it mixes Tet4 and Tet10 (then setOrder makes them alike).
int tet_order() {
  std::vector<int> types;
  gmsh::model::mesh::getElementTypes(types, 3);
  const bool p1 = std::count(types.begin(), types.end(), 4) > 0;
  const bool p2 = std::count(types.begin(), types.end(), 11) > 0;
  return p1 && p2 ? -1 : p2 ? 2 : p1 ? 1 : 0;
}

void refine_and_set_order(const MeshConfig& cfg, int current_order) {
  if (cfg.refine > 0 && current_order != 1) gmsh::model::mesh::setOrder(1);
  for (int i = 0; i < cfg.refine; ++i) gmsh::model::mesh::refine();
  if (cfg.refine > 0) current_order = 1;
  if (current_order != cfg.order) gmsh::model::mesh::setOrder(cfg.order);
}

Mesh load_with_gmsh(const MeshConfig& cfg, bool is_geo) {
  std::unique_ptr<ParameterWrapper> wrapper;
  if (is_geo && !cfg.parameters.empty())
    wrapper = std::make_unique<ParameterWrapper>(cfg.file, cfg.parameters);
  GmshSession session;
  try {
    gmsh::open(wrapper ? wrapper->path() : cfg.file);
    if (is_geo) {
      // Meshed in one call: meshing a dimension at a time (to count the triangles first)
      // makes other tetrahedra than gmsh -3 does, and the meshes must stay the same.
      check_size_estimate(cfg);
      const GmshErrorReport report(cfg.file);
      gmsh::model::mesh::generate(3);
    }
    check_tetrahedra_only(cfg.file);
    const int order = tet_order();
    if (order == 0) throw InputError(cfg.file + ": the mesh contains no tetrahedra");
    const double tets = static_cast<double>(element_count(3));
    check_tet_count(cfg, tets, "the mesh has " + count_text(tets) + " tetrahedra");
    refine_and_set_order(cfg, is_geo ? 1 : order);
    return mesh_from_gmsh_model(cfg.file, cfg.order);
  } catch (const std::exception&) {  // ours (InputError) and the standard library's
    throw;
  } catch (...) {  // gmsh's own errors (thrown with General.AbortOnError = 2)
    std::string error;
    gmsh::logger::getLastError(error);
    throw InputError(cfg.file + ": gmsh: " + (error.empty() ? "unknown error" : error));
  }
}

}  // namespace

Mesh load_mesh(const MeshConfig& cfg) {
  const std::string& file = cfg.file;
  if (cfg.order != 1 && cfg.order != 2)
    throw InputError(file + ": mesh.order must be 1 or 2, not " + std::to_string(cfg.order));
  if (cfg.refine < 0)
    throw InputError(file + ": mesh.refine must be >= 0, not " + std::to_string(cfg.refine));
  if (cfg.max_elements < 1)
    throw InputError(file + ": mesh.max_elements must be >= 1, not " +
                     std::to_string(cfg.max_elements));
  std::string extension = fs::path(file).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const bool is_geo = extension == ".geo";
  if (!is_geo && extension != ".msh")
    throw InputError(file + ": unknown mesh file type '" + extension + "' (.msh or .geo)");
  if (!is_geo && !cfg.parameters.empty())
    throw InputError(file + ": mesh.parameters apply to .geo files only");
  open_input(file);  // gmsh reports a missing file only as a warning
  if (is_geo && !cfg.trust_geo) check_untrusted_geo(file, {cfg.deck_dir});
  if (!is_geo) {
    const MshCounts counts = prescan_msh(file);
    if (counts.tets >= 0)
      check_tet_count(cfg, static_cast<double>(counts.tets),
                      "its $Elements section holds " + std::to_string(counts.tets) + " tetrahedra");
  }
  return load_with_gmsh(cfg, is_geo);
}

void require_group(const Mesh& mesh, const std::string& name, const std::string& where) {
  const auto it = mesh.node_groups.find(name);
  if (it != mesh.node_groups.end() && !it->second.empty()) return;
  std::string known;
  for (const auto& [group, nodes] : mesh.node_groups) known += (known.empty() ? "" : ", ") + group;
  throw InputError(where + ": the mesh has no group '" + name +
                   "' (its groups: " + (known.empty() ? "none" : known) + ")");
}

}  // namespace hs
