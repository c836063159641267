// parse_deck: YAML -> Config, validating every key before any work (docs/decks.md).
#include "deck/deck.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>

#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "deck/cable_section.hpp"
#include "deck/cavity_sections.hpp"
#include "deck/control_section.hpp"
#include "deck/exact_section.hpp"
#include "deck/overrides.hpp"
#include "deck/run_sections.hpp"
#include "io/output.hpp"
#include "materials/registry.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;

YAML::Node load_yaml(const std::string& path) {
  std::error_code error;  // a name too long for the system is a missing file, not an exception
  if (!fs::is_regular_file(path, error))
    throw InputError(printable(path) + ": deck file not found" +
                     (error && error != std::errc::no_such_file_or_directory
                          ? " (" + error.message() + ")"
                          : ""));
  try {
    // A second document (after ---) would be ignored: refused rather than half-read.
    const std::vector<YAML::Node> documents = YAML::LoadAllFromFile(path);
    if (documents.size() > 1)
      throw InputError(path + ": line " + std::to_string(documents[1].Mark().line + 1) +
                       ": a second YAML document; a deck is one document (remove the '---')");
    return documents.empty() ? YAML::Node() : documents[0];
  } catch (const YAML::ParserException& e) {
    throw InputError(path + ": line " + std::to_string(e.mark.line + 1) + ", column " +
                     std::to_string(e.mark.column + 1) + ": invalid YAML: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": cannot read the deck: " + e.msg);
  }
}

MeshConfig parse_mesh(const DeckReader& r, const YAML::Node& node, const fs::path& deck_dir) {
  const std::string key = "mesh";
  r.check_map(node, key, {"file", "order", "parameters", "refine", "trust_geo", "max_elements"});
  MeshConfig mesh;
  const YAML::Node file = required(r, node, key, "file");
  const fs::path given = r.text(file, "mesh.file");
  const fs::path resolved = fs::absolute(given.is_absolute() ? given : deck_dir / given);
  mesh.file = resolved.lexically_normal().string();
  std::error_code error;  // a name too long for the system is a missing file, not an exception
  if (!fs::is_regular_file(mesh.file, error))
    r.fail(
        "mesh.file", file,
        "mesh file '" + (mesh.file.size() > 200 ? mesh.file.substr(0, 200) + "..." : mesh.file) +
            "' not found (a relative path starts at the deck's folder" +
            (error && error != std::errc::no_such_file_or_directory ? "; " + error.message() : "") +
            ")");
  std::string extension = resolved.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  require(extension == ".msh" || extension == ".geo" || extension == ".h5", r, file, "mesh.file",
          "expected a .msh, .geo or .h5 (hydrosoft mesh) file, got '" + extension + "'");
  if (const auto n = node["order"]) {
    require(extension != ".h5", r, n, "mesh.order",
            "an .h5 mesh keeps the order it was meshed at (set it when meshing)");
    mesh.order = r.integer(n, "mesh.order");
    require(mesh.order == 1 || mesh.order == 2, r, n, "mesh.order", "must be 1 or 2");
  }
  const std::string geo_only = "only used with a .geo mesh file";
  if (const auto n = node["parameters"]) {
    require(extension == ".geo", r, n, "mesh.parameters", geo_only);
    mesh.parameters = r.number_map(n, "mesh.parameters");
  }
  if (const auto n = node["refine"]) {
    require(extension == ".geo", r, n, "mesh.refine", geo_only);
    mesh.refine = r.integer(n, "mesh.refine");
    require(mesh.refine >= 0, r, n, "mesh.refine", "must be >= 0");
  }
  if (const auto n = node["trust_geo"]) {
    require(extension == ".geo", r, n, "mesh.trust_geo", geo_only);
    mesh.trust_geo = r.boolean(n, "mesh.trust_geo");
  }
  if (const auto n = node["max_elements"]) {
    mesh.max_elements = r.integer(n, "mesh.max_elements");
    require(mesh.max_elements >= 1, r, n, "mesh.max_elements", "must be >= 1");
  }
  mesh.deck_dir =
      (deck_dir.empty() ? fs::current_path() : fs::absolute(deck_dir)).lexically_normal().string();
  return mesh;
}

// The deck owns group and density; the registry reads the model's law from the rest of the map.
MaterialConfig parse_material(const DeckReader& r, const YAML::Node& node, const std::string& key) {
  const std::vector<std::string> deck_keys = {"group", "model", "density"};
  std::vector<std::string> known = {"group", "model"};
  for (const auto& name : material_law_keys()) known.push_back(name);
  known.push_back("density");
  r.check_map(node, key, known);
  MaterialConfig m;
  m.group = r.text(required(r, node, key, "group"), child_key(key, "group"));
  const std::string model = r.text(required(r, node, key, "model"), child_key(key, "model"));
  m.law = parse_material_law(r, node, key, model, deck_keys);
  if (const auto n = node["density"]) {
    m.density = r.number(n, child_key(key, "density"));
    require(m.density >= 0, r, n, child_key(key, "density"),
            "must be >= 0, got " + format_number(m.density));
    // Above any solid's (osmium: 22,590 kg/m^3), and far from where rho g overflows.
    require(m.density <= 1e5, r, n, child_key(key, "density"),
            "must be <= 1e5 kg/m^3, got " + format_number(m.density));
  }
  return m;
}

std::vector<MaterialConfig> parse_materials(const DeckReader& r, const YAML::Node& node) {
  r.check_list(node, "materials");
  require(node.size() > 0, r, node, "materials", "at least one material is required");
  std::vector<MaterialConfig> materials;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = item_key("materials", i);
    materials.push_back(parse_material(r, node[i], key));
    for (size_t j = 0; j < i; ++j)
      if (materials[j].group == materials[i].group)
        r.fail(child_key(key, "group"), node[i]["group"],
               "duplicate material group '" + materials[i].group + "' (also in " +
                   item_key("materials", j) + ")");
  }
  return materials;
}

DirichletConfig parse_boundary(const DeckReader& r, const YAML::Node& node,
                               const std::string& key) {
  r.check_map(node, key, {"group", "components", "value", "scaled", "exact"});
  DirichletConfig bc;
  bc.group = r.text(required(r, node, key, "group"), child_key(key, "group"));
  if (const auto n = node["components"]) {
    const std::string ckey = child_key(key, "components");
    r.check_list(n, ckey);
    require(n.size() > 0, r, n, ckey, "must name at least one of x, y, z");
    bc.components = {false, false, false};
    for (size_t i = 0; i < n.size(); ++i) {
      const std::string c = one_of(r, n[i], item_key(ckey, i), {"x", "y", "z"});
      bool& on = bc.components[c[0] - 'x'];
      require(!on, r, n[i], item_key(ckey, i), "component '" + c + "' named twice");
      on = true;
    }
  }
  if (const auto n = node["value"]) bc.value = r.vector3(n, child_key(key, "value"));
  if (const auto n = node["scaled"]) bc.scaled = r.boolean(n, child_key(key, "scaled"));
  if (const auto n = node["exact"]) bc.exact = r.boolean(n, child_key(key, "exact"));
  if (bc.exact) forbid(r, node, key, "value", "not used when exact is true");
  return bc;
}

void parse_loads(const DeckReader& r, const YAML::Node& node, Config& c) {
  r.check_map(node, "loads", {"gravity", "pressure"});
  if (const auto n = node["gravity"]) {
    c.gravity = r.vector3(n, "loads.gravity");
    // A thousand g: beyond any robot's, and far from where rho g overflows.
    for (double g : c.gravity)
      require(std::abs(g) <= 1e4, r, n, "loads.gravity",
              "each component must be within +-1e4 m/s^2, got " + format_number(g));
  }
  if (const auto list = node["pressure"]) {
    r.check_list(list, "loads.pressure");
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string key = item_key("loads.pressure", i);
      r.check_map(list[i], key, {"group", "value"});
      PressureConfig p;
      p.group = r.text(required(r, list[i], key, "group"), child_key(key, "group"));
      p.value = r.number(required(r, list[i], key, "value"), child_key(key, "value"));
      c.pressures.push_back(p);
    }
  }
}

}  // namespace

Config parse_deck(const std::string& path, const std::vector<std::string>& overrides) {
  YAML::Node root = load_yaml(path);
  const DeckReader r(path, apply_overrides(root, overrides, path));
  if (root.IsNull()) r.fail("mesh", "required key missing (the deck is empty)");
  if (!root.IsMap())
    r.fail("(top level)", root, "expected a map of sections (mesh, materials, ...)");
  r.check_map(root, "",
              {"mesh", "materials", "boundary", "loads", "cavities", "cables", "time", "states",
               "tip", "control", "solver", "output", "exact"});

  Config c;
  c.deck_path = path;
  c.deck_name = fs::path(path).stem().string();
  c.mesh = parse_mesh(r, required(r, root, "", "mesh"), fs::path(path).parent_path());
  c.materials = parse_materials(r, required(r, root, "", "materials"));
  if (const auto list = root["boundary"]) {
    r.check_list(list, "boundary");
    for (size_t i = 0; i < list.size(); ++i)
      c.dirichlet.push_back(parse_boundary(r, list[i], item_key("boundary", i)));
  }
  if (const auto n = root["loads"]) parse_loads(r, n, c);
  if (const auto n = root["time"]) c.time = parse_time(r, n, c);
  parse_cavity_sections(r, root, c);
  parse_cable_section(r, root, c);
  parse_control_section(r, root, c);  // its actuators are cavities and cables
  if (const auto n = root["solver"]) c.solver = parse_solver(r, n, c);
  if (const auto n = root["output"]) c.output = parse_output(r, n, c);
  if (c.output.folder.empty()) c.output.folder = (fs::path("out") / c.deck_name).string();
  const std::string problem = output_folder_problem(c.output.folder);
  if (!problem.empty()) {
    const YAML::Node output = root["output"];
    if (output && output.IsMap() && output["folder"])
      r.fail("output.folder", output["folder"], problem);
    r.fail("output.folder", "the default '" + c.output.folder + "': " + problem);
  }
  // The results go to <deck name>.h5 beside checkpoint.h5: a deck named checkpoint would write
  // both into one file.
  if (c.output.checkpoint && c.deck_name == "checkpoint")
    r.fail("output.checkpoint", root["output"]["checkpoint"],
           "a deck named checkpoint.yaml writes its results to checkpoint.h5, the checkpoint's own "
           "file: rename the deck");
  // The one_step controller uses the liquids' weights frozen wherever they were last frozen,
  // which a checkpoint does not hold (a restart would freeze them elsewhere).
  if (c.output.checkpoint && c.control && c.control->free_solve == FreeSolve::one_step)
    for (const auto& cavity : c.cavities)
      if (cavity.kind == CavityKind::hydraulic &&
          cavity.fluid_weight.coupling == WeightCoupling::linearized)
        r.fail("output.checkpoint", root["output"]["checkpoint"],
               "not supported with control.free_solve one_step and a hydraulic cavity's "
               "fluid_weight.coupling linearized (the frozen weights are not saved, so such a "
               "run cannot be restarted to the same numbers)");
  parse_exact_section(r, root, c);
  for (size_t i = 0; i < c.dirichlet.size(); ++i)
    if (c.dirichlet[i].exact && !c.exact.type)
      r.fail(child_key(item_key("boundary", i), "exact"), root["boundary"][i]["exact"],
             "needs an exact solution, but exact.type is none");
  return c;
}

}  // namespace hs
