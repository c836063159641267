// parse_deck: YAML -> Config, validating every key before any work (docs/decks.md).
#include "deck/deck.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>

#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "deck/body_sections.hpp"
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
  c.mesh = parse_mesh(r, required(r, root, "", "mesh"), fs::path(path).parent_path().string(), c);
  c.materials = parse_materials(r, required(r, root, "", "materials"));
  if (const auto list = root["boundary"]) {
    r.check_list(list, "boundary");
    for (size_t i = 0; i < list.size(); ++i)
      c.dirichlet.push_back(parse_boundary(r, list[i], item_key("boundary", i), c));
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
