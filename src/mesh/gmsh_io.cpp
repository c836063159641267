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

#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "mesh/geo_guard.hpp"
#include "mesh/gmsh_model.hpp"
#include "mesh/gmsh_process.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_h5.hpp"
#include "mesh/mesh_size_limit.hpp"
#include "mesh/msh_prescan.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;

// One gmsh session per load, quiet (errors reach the user through InputError, a .geo's Printf
// lines through PrintfRelay), single threaded (reproducible meshes), finalised on every way out.
class GmshSession {
 public:
  GmshSession() {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    // Level 3 logs a .geo's Printf ("Direct") and gmsh's warnings, not its progress ("Info").
    gmsh::option::setNumber("General.Verbosity", 3);
    gmsh::logger::start();
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

// The .geo text with its comments and strings blanked: a parameter named only in a comment
// ("// A selection that ...") or a message is not used by the file.
std::string code_only(const std::string& text) {
  std::string code = text;
  for (size_t i = 0; i < code.size(); ++i) {
    size_t end = i;
    if (code.compare(i, 2, "//") == 0) {
      end = code.find('\n', i);
    } else if (code.compare(i, 2, "/*") == 0) {
      end = code.find("*/", i + 2);
      if (end != std::string::npos) end += 2;
    } else if (code[i] == '"') {
      end = i + 1;
      while (end < code.size() && code[end] != '"' && code[end] != '\n')
        end += code[end] == '\\' ? 2 : 1;
      end = std::min(end + 1, code.size());
    } else {
      continue;
    }
    if (end == std::string::npos) end = code.size();
    for (size_t k = i; k < end; ++k)
      if (code[k] != '\n') code[k] = ' ';
    i = end - 1;
  }
  return code;
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
  int fd() const { return fd_; }

 private:
  static std::string wrapper_text(const std::string& file,
                                  const std::map<std::string, double>& parameters) {
    const std::string source = read_text(file);
    const std::string code = code_only(source);
    const std::string absolute = fs::absolute(file).lexically_normal().string();
    if (absolute.find('"') != std::string::npos)
      throw InputError(file + ": a .geo path with a double quote cannot be included");
    std::ostringstream geo;
    geo.precision(17);
    for (const auto& [name, value] : parameters) {
      const std::string where = file + ": mesh parameter '" + printable(name) + "'";
      if (!is_identifier(name)) throw InputError(where + " is not a .geo identifier");
      if (!std::isfinite(value)) throw InputError(where + " is not a finite number");
      if (!mentions(code, name))
        throw InputError(where + " does not occur in the file (outside its comments and strings)");
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

// A .geo's Printf lines, which gmsh logs as "Direct: TEXT", go to the user as "hydrosoft:
// FILE: TEXT" (tell_user) on every way out of the meshing: a .geo that fails after printing
// shows what it printed. gmsh's own warnings stay in the log (many are harmless).
class PrintfRelay {
 public:
  explicit PrintfRelay(const std::string& file) : file_(file) {}
  ~PrintfRelay() {
    try {
      std::vector<std::string> log;
      gmsh::logger::get(log);
      static const std::string kPrintf = "Direct: ";
      for (const std::string& line : log)
        if (line.compare(0, kPrintf.size(), kPrintf) == 0)
          tell_user("hydrosoft: " + file_ + ": " + line.substr(kPrintf.size()));
    } catch (...) {  // the mesh or the error on its way out matters more than the lines
    }
  }
  PrintfRelay(const PrintfRelay&) = delete;
  PrintfRelay& operator=(const PrintfRelay&) = delete;

 private:
  std::string file_;
};

// In gmsh's own process (gmsh_process.hpp).
Mesh mesh_with_gmsh(const MeshConfig& cfg, bool is_geo, const std::string& path) {
  GmshSession session;
  PrintfRelay printed(cfg.file);
  try {
    gmsh::open(path);
    if (is_geo) {
      // Meshed in one call: meshing a dimension at a time (to count the triangles first)
      // makes other tetrahedra than gmsh -3 does, and the meshes must stay the same.
      check_size_estimate(cfg);
      gmsh::model::mesh::generate(3);
    }
    check_tetrahedra_only(cfg.file);
    const int order = tet_order();
    if (order == 0) throw InputError(cfg.file + ": the mesh contains no tetrahedra");
    check_meshed_tet_count(cfg);
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

Mesh load_with_gmsh(const MeshConfig& cfg, bool is_geo) {
  // The parameters' wrapper is written here, before the child is confined (it then cannot
  // write any file, in-memory ones included), and handed to it open.
  std::unique_ptr<ParameterWrapper> wrapper;
  if (is_geo && !cfg.parameters.empty())
    wrapper = std::make_unique<ParameterWrapper>(cfg.file, cfg.parameters);
  const std::string path = wrapper ? wrapper->path() : cfg.file;
  GmshProcess how;
  how.confined = !(is_geo && cfg.trust_geo);
  if (wrapper) how.keep.push_back(wrapper->fd());
  return run_gmsh_process(
      cfg.file, [&] { return mesh_with_gmsh(cfg, is_geo, path); }, how);
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
  if (extension == ".h5") {  // a hydrosoft mesh, whole, on this process, checked as a run reads it
    Mesh mesh = whole_mesh(read_mesh_h5(file, cfg.max_elements, MPI_COMM_SELF));
    if (const std::string warning = quality_warning(mesh, file); !warning.empty())
      tell_user("hydrosoft: warning: " + warning);
    return mesh;
  }
  if (!is_geo && extension != ".msh")
    throw InputError(file + ": unknown mesh file type '" + extension + "' (.msh, .geo or .h5)");
  if (!is_geo && !cfg.parameters.empty())
    throw InputError(file + ": mesh.parameters apply to .geo files only");
  open_input(file);  // gmsh reports a missing file only as a warning
  if (is_geo && !cfg.trust_geo) check_untrusted_geo(file, {cfg.deck_dir});
  if (!is_geo) {
    check_untrusted_msh(file, {cfg.deck_dir});
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
