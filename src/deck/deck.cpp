// parse_deck: YAML -> Config, validating every key before any work (docs/decks.md).
#include "deck/deck.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "deck/overrides.hpp"
#include "deck/section_keys.hpp"
#include "io/output.hpp"

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

}  // namespace

Config parse_deck(const std::string& path, const std::vector<std::string>& overrides) {
  YAML::Node root = load_yaml(path);
  const DeckReader r(path, apply_overrides(root, overrides, path));
  if (root.IsNull()) r.fail("mesh", "required key missing (the deck is empty)");
  if (!root.IsMap())
    r.fail("(top level)", root, "expected a map of sections (mesh, materials, ...)");
  const KeyTable<Config>& sections = deck_section_keys();
  r.check_map(root, "", key_names(sections));

  Config c;
  c.deck_path = path;
  c.deck_name = fs::path(path).stem().string();
  // In the order they depend on each other: cavities, cables, states and control need the
  // time section's type; states and control name cavities and cables.
  const std::vector<std::string> order = {
      "mesh", "materials", "boundary", "loads",   "time",   "cavities", "cables", "states",
      "tip",  "obstacles", "contact",  "control", "solver", "output",   "exact"};
  if (order.size() != sections.size()) throw std::logic_error("parse_deck: a section unread");
  for (const std::string& name : order) {
    const auto k = std::find_if(sections.begin(), sections.end(),
                                [&](const DeckKey<Config>& k) { return k.name == name; });
    read_key(r, root, "", *k, c, c);
    // time.steps and time.schedule are not used with states (read after time).
    if (name == "states" && root["states"] && root["time"])
      check_uses(r, root["time"], "time", time_keys(), c.time, c);
  }
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
  if (root["contact"] && c.obstacles.empty() && !c.contact.self)
    r.fail("contact", root["contact"],
           "only used with obstacles or contact.self (the section obstacles is empty and "
           "self is false)");
  if (!c.contact.friction_between.empty() && !c.contact.self)
    r.fail("contact.friction_between", root["contact"]["friction_between"],
           "is friction between the contact surfaces, which touch each other only with "
           "contact.self: true");
  bool between = false;
  for (const auto& f : c.contact.friction_between) between |= f.friction > 0;
  if (between && c.output.checkpoint)
    r.fail("contact.friction_between", root["contact"]["friction_between"],
           "friction between the surfaces is not supported with output.checkpoint (its lagged "
           "state is not saved, so a restart would not continue the same run)");
  if (c.contact.friction > 0 && !c.contact.self)
    r.fail("contact.friction", root["contact"]["friction"],
           "is friction between the contact surfaces, which touch each other only with "
           "contact.self: true (an obstacle's friction is its own key)");
  if (c.contact.friction > 0 && c.output.checkpoint)
    r.fail("contact.friction", root["contact"]["friction"],
           "friction is not supported with output.checkpoint (its lagged state is not saved, "
           "so a restart would not continue the same run)");
  if (c.control && c.control->contact_forces == ContactForces::qp) {
    const YAML::Node node = root["control"]["contact_forces"];
    const std::string key = "control.contact_forces";
    auto refuse = [&](const std::string& why) { r.fail(key, node, "qp " + why); };
    if (c.obstacles.empty()) refuse("needs obstacles (its unknowns are their contact forces)");
    for (const auto& o : c.obstacles)
      if (o.friction > 0)
        refuse("takes normal forces only: obstacle '" + o.name +
               "' has friction (use free_step, whose barrier carries friction)");
    if (c.contact.self)
      refuse("is not supported with contact.self (its pairs stay the barrier's: use free_step)");
    if (c.control->free_solve == FreeSolve::one_step)
      refuse(
          "needs free_solve: newton (the held forces are converged with each free "
          "configuration)");
    if (!c.control->reduced_model.empty()) refuse("is not supported with control.reduced_model");
    if (c.output.checkpoint)
      refuse("is not supported with output.checkpoint (the held forces are not saved)");
    for (const auto& moves : c.control->moves)
      if (!moves.empty()) refuse("is not supported with a target set's move");
  }
  for (size_t k = 0; c.control && k < c.control->moves.size(); ++k) {
    if (c.control->moves[k].empty()) continue;
    const std::string key = child_key(item_key("control.targets", k), "move");
    const YAML::Node node = root["control"]["targets"][k]["move"];
    if (c.output.checkpoint)
      r.fail(key, node,
             "not supported with output.checkpoint (a restart does not restore the moved "
             "groups' values)");
    if (!c.control->reduced_model.empty())
      r.fail(key, node,
             "not supported with control.reduced_model (its basis holds the "
             "boundary's values fixed)");
    if (c.control->free_solve == FreeSolve::one_step)
      r.fail(key, node,
             "not supported with control.free_solve one_step (its single linearisation does not "
             "carry the boundary's move: use newton)");
  }
  for (size_t k = 0; k < c.states.size() && c.output.checkpoint; ++k)
    if (!c.states[k].moves.empty())
      r.fail(child_key(item_key("states", k), "move"), root["states"][k]["move"],
             "not supported with output.checkpoint (a restart does not restore the moved "
             "groups' values)");
  if (!c.obstacles.empty() && c.contact.surfaces.empty())
    r.fail("contact",
           "required with obstacles: contact.surfaces names the body's surface "
           "groups that may touch them");
  // Friction's lag (the step's start positions and normal forces) is not saved in a
  // checkpoint.
  for (size_t i = 0; i < c.obstacles.size(); ++i) {
    if (c.obstacles[i].friction == 0) continue;
    const YAML::Node node = root["obstacles"][i]["friction"];
    const std::string key = child_key(item_key("obstacles", i), "friction");
    if (c.output.checkpoint)
      r.fail(key, node,
             "friction is not supported with output.checkpoint (its lagged state "
             "is not saved, so a restart would not continue the same run)");
  }
  for (size_t i = 0; i < c.dirichlet.size(); ++i)
    if (c.dirichlet[i].exact && !c.exact.type)
      r.fail(child_key(item_key("boundary", i), "exact"), root["boundary"][i]["exact"],
             "needs an exact solution, but exact.type is none");
  return c;
}

}  // namespace hs
