// The sections `mesh`, `boundary` and `loads`: their key tables and parsers (docs/decks.md).
#include "deck/body_sections.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>

#include "deck/section_keys.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;

// The mesh file's extension in lower case: .msh, .geo or .h5 once mesh.file is read.
std::string extension_of(const MeshConfig& mesh) {
  std::string extension = fs::path(mesh.file).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

KeyUse<MeshConfig> geo_only() {
  return use_when<MeshConfig>(
      [](const MeshConfig& mesh, const Config&) { return extension_of(mesh) == ".geo"; },
      "only used with a .geo mesh file", "`.geo` only");
}

}  // namespace

const KeyTable<MeshConfig>& mesh_keys() {
  static const KeyTable<MeshConfig> keys = {
      custom_key<MeshConfig>(
          "file", "path", "required",
          "gmsh mesh (`.msh`, format 4), gmsh source (`.geo`, meshed at start) or hydrosoft "
          "mesh (`.h5`, written by `hydrosoft mesh DECK OUT.h5`; every rank reads its own part "
          "in parallel, see \"Meshing once\" below). A relative path starts at the deck's "
          "folder.",
          [](const DeckReader& r, const YAML::Node& file, const std::string& key, MeshConfig& mesh,
             const Config&) {
            const fs::path given = r.text(file, key);
            const fs::path resolved =
                fs::absolute(given.is_absolute() ? given : fs::path(mesh.deck_dir) / given);
            mesh.file = resolved.lexically_normal().string();
            std::error_code error;  // a name too long for the system is a missing file
            if (!fs::is_regular_file(mesh.file, error))
              r.fail(key, file,
                     "mesh file '" +
                         (mesh.file.size() > 200 ? mesh.file.substr(0, 200) + "..." : mesh.file) +
                         "' not found (a relative path starts at the deck's folder" +
                         (error && error != std::errc::no_such_file_or_directory
                              ? "; " + error.message()
                              : "") +
                         ")");
            const std::string extension = extension_of(mesh);
            require(extension == ".msh" || extension == ".geo" || extension == ".h5", r, file, key,
                    "expected a .msh, .geo or .h5 (hydrosoft mesh) file, got '" + extension + "'");
          },
          [](YAML::Emitter& out, const MeshConfig& mesh, const Config&) { out << mesh.file; })
          .needed(),
      integer_key(
          "order", &MeshConfig::order,
          Limit{"1 or 2", [](double x) { return x == 1 || x == 2 ? "" : "must be 1 or 2"; }},
          "element order: 1 = 4-node tetrahedra (P1), 2 = 10-node tetrahedra (P2); not "
          "with an `.h5`, which keeps the order it was meshed at")
          .only(use_when<MeshConfig>(
              [](const MeshConfig& mesh, const Config&) { return extension_of(mesh) != ".h5"; },
              "an .h5 mesh keeps the order it was meshed at (set it when meshing)", "")),
      custom_key<MeshConfig>(
          "parameters", "map name: number", "none",
          "numbers set before meshing (e.g. `h`, the target size in m); each must occur in the "
          "`.geo`",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, MeshConfig& mesh,
             const Config&) { mesh.parameters = r.number_map(n, key); },
          [](YAML::Emitter& out, const MeshConfig& mesh, const Config&) {
            out << YAML::Flow << YAML::BeginMap;
            for (const auto& [name, value] : mesh.parameters)
              out << YAML::Key << name << YAML::Value << format_number(value);
            out << YAML::EndMap;
          })
          .only(geo_only()),
      integer_key("refine", &MeshConfig::refine, at_least(0), "uniform refinements after meshing")
          .only(geo_only()),
      bool_key("trust_geo", &MeshConfig::trust_geo,
               "run the `.geo` as it is. A `.geo` is gmsh code; an untrusted one (the default) is "
               "refused before meshing when it runs a command (`SystemCall`, `System`, "
               "`OnelabRun`, `Exit`, ...), writes or removes files (`Save`, `Print`, `Printf(...) "
               "> file`, `CreateDir`, `DeleteFile`), asks on standard input, sets an option "
               "naming a file or a program, or reads or names a file outside its own folder and "
               "the deck's folder (`Include \"/etc/passwd\"`). Every `.geo` of `meshes/` passes.")
          .only(geo_only()),
      integer_key("max_elements", &MeshConfig::max_elements, at_least(1),
                  "the most tetrahedra the mesh may have, after `refine`. A `.geo` is refused "
                  "before meshing when its size options (`Mesh.MeshSizeMax`) already promise "
                  "more, and after meshing when it made more; a `.msh` when its `$Elements` "
                  "header holds more; an `.h5` when its `/tets` holds more, before it is read."),
  };
  return keys;
}

const KeyTable<DirichletConfig>& boundary_keys() {
  static const KeyTable<DirichletConfig> keys = {
      text_key("group", &DirichletConfig::group, "name",
               "physical group of any dimension (surface, curve, point, volume)")
          .needed(),
      custom_key<DirichletConfig>(
          "components", "list of `x`, `y`, `z`", "`[x, y, z]`",
          "the displacement components prescribed (a list, even for one)",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, DirichletConfig& bc,
             const Config&) { bc.components = read_axes(r, n, key, "component"); },
          [](YAML::Emitter& out, const DirichletConfig& bc, const Config&) {
            write_axes(out, bc.components);
          }),
      custom_key<DirichletConfig>(
          "value", "3 numbers", "`[0, 0, 0]`",
          "prescribed displacement (m) at full load, one entry per axis; entries of components "
          "not listed are ignored",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, DirichletConfig& bc,
             const Config&) { bc.value = r.vector3(n, key); },
          [](YAML::Emitter& out, const DirichletConfig& bc, const Config&) {
            write_numbers(out, bc.value.data(), 3);
          })
          .only(use_when<DirichletConfig>(
              [](const DirichletConfig& bc, const Config&) { return !bc.exact; },
              "not used when exact is true", "")),
      bool_key("scaled", &DirichletConfig::scaled,
               "the value follows the load factor (false: applied in full from the first step)"),
      bool_key("exact", &DirichletConfig::exact,
               "the values come from the deck's exact solution at the current load factor "
               "(verification decks; needs `exact.type` other than `none`; excludes `value`)"),
  };
  return keys;
}

const KeyTable<PressureConfig>& pressure_keys() {
  static const KeyTable<PressureConfig> keys = {
      text_key("group", &PressureConfig::group, "name", "surface physical group").needed(),
      number_key("value", &PressureConfig::value, any_number(), "Pa at full load").needed(),
  };
  return keys;
}

const KeyTable<TractionConfig>& traction_keys() {
  static const KeyTable<TractionConfig> keys = {
      text_key("group", &TractionConfig::group, "name", "surface physical group").needed(),
      custom_key<TractionConfig>(
          "value", "3 numbers", "required", "force per reference area (Pa) at full load",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, TractionConfig& t,
             const Config&) { t.value = r.vector3(n, key); },
          [](YAML::Emitter& out, const TractionConfig& t, const Config&) {
            write_numbers(out, t.value.data(), 3);
          })
          .needed(),
  };
  return keys;
}

namespace {

// A list of `{group, value}` loads of `loads`, each entry a flow map of `keys` ("[]" when empty).
template <class Load>
DeckKey<Config> surface_load_list(std::string name, std::vector<Load> Config::*member,
                                  const KeyTable<Load>& (*keys)(), std::string meaning) {
  return custom_key<Config>(
      std::move(name), "list of `{group, value}`", "none", std::move(meaning),
      [member, keys](const DeckReader& r, const YAML::Node& list, const std::string& key, Config& c,
                     const Config&) {
        r.check_list(list, key);
        for (size_t i = 0; i < list.size(); ++i) {
          Load load;
          read_keys(r, list[i], item_key(key, i), keys(), load, c);
          (c.*member).push_back(load);
        }
      },
      [member, keys](YAML::Emitter& out, const Config& c, const Config&) {
        if ((c.*member).empty()) out << YAML::Flow;
        out << YAML::BeginSeq;
        for (const auto& load : c.*member) {
          out << YAML::Flow << YAML::BeginMap;
          write_keys(out, keys(), load, c);
          out << YAML::EndMap;
        }
        out << YAML::EndSeq;
      });
}

}  // namespace

const KeyTable<Config>& loads_keys() {
  static const KeyTable<Config> keys = {
      custom_key<Config>(
          "gravity", "3 numbers, each within ±1e4", "`[0, 0, 0]`",
          "acceleration of gravity (m/s²), e.g. `[0, 0, -9.81]`; body force density × gravity",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, Config& c,
             const Config&) {
            c.gravity = r.vector3(n, key);
            // A thousand g: beyond any robot's, and far from where rho g overflows.
            for (double g : c.gravity)
              require(std::abs(g) <= 1e4, r, n, key,
                      "each component must be within +-1e4 m/s^2, got " + format_number(g));
          },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_numbers(out, c.gravity.data(), 3);
          }),
      surface_load_list("pressure", &Config::pressures, pressure_keys,
                        "follower pressure (Pa) on a surface group at full load; positive pushes "
                        "against the outward normal (into the body), negative pulls"),
      surface_load_list("traction", &Config::tractions, traction_keys,
                        "dead traction on a surface group: `value` the force per reference area "
                        "(Pa, 3 numbers) at full load, fixed in direction and size as the body "
                        "deforms (a shear load, a hanging weight spread over a face)")
          .printed_when([](const Config& c) { return !c.tractions.empty(); }),
  };
  return keys;
}

MeshConfig parse_mesh(const DeckReader& r, const YAML::Node& node, const std::string& deck_dir,
                      const Config& c) {
  MeshConfig mesh;
  mesh.deck_dir =
      (deck_dir.empty() ? fs::current_path() : fs::absolute(deck_dir)).lexically_normal().string();
  read_keys(r, node, "mesh", mesh_keys(), mesh, c);
  return mesh;
}

DirichletConfig parse_boundary(const DeckReader& r, const YAML::Node& node, const std::string& key,
                               const Config& c) {
  DirichletConfig bc;
  read_keys(r, node, key, boundary_keys(), bc, c);
  return bc;
}

void parse_loads(const DeckReader& r, const YAML::Node& node, Config& c) {
  read_keys(r, node, "loads", loads_keys(), c, c);
}

}  // namespace hs
