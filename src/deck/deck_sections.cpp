// The deck's sections as the keys of its top-level map (deck/section_keys.hpp): what each
// holds, how it is read and printed, and the section a dynamic run has no use for (control).
// Materials are read and printed here: the deck owns a material's group and density, the
// registry of src/materials/ its model's keys.
#include <filesystem>

#include "deck/body_sections.hpp"
#include "deck/cable_section.hpp"
#include "deck/cavity_sections.hpp"
#include "deck/contact_section.hpp"
#include "deck/control_section.hpp"
#include "deck/element_formulation.hpp"
#include "deck/exact_section.hpp"
#include "deck/run_sections.hpp"
#include "deck/section_keys.hpp"
#include "materials/material.hpp"
#include "materials/registry.hpp"

namespace hs {
namespace {

MaterialConfig parse_material(const DeckReader& r, const YAML::Node& node, const std::string& key,
                              const Config& c) {
  const std::vector<std::string> deck_keys = key_names(material_keys());
  std::vector<std::string> known;  // the models' keys after `model`, as printed
  for (const auto& name : deck_keys) {
    known.push_back(name);
    if (name == "model")
      for (const auto& law_key : material_law_keys()) known.push_back(law_key);
  }
  r.check_map(node, key, known);
  MaterialConfig m;
  for (const auto& k : material_keys()) {
    if (k.read) {
      read_key(r, node, key, k, m, c);
      continue;
    }
    // `model`: its law, from the whole map.
    const std::string model = r.text(required(r, node, key, k.name), child_key(key, k.name));
    m.law = parse_material_law(r, node, key, model, deck_keys);
  }
  const FormulationChoice choice =
      choose_formulation(m.formulation, m.law->elastic_constants().nu, c.mesh.order,
                         m.law->has_volumetric_term(), m.law->small_strain());
  if (!choice.error.empty())
    r.fail(child_key(key, choice.error_key), node[choice.error_key], choice.error);
  m.element = choice.formulation;
  m.formulation_reason = choice.reason;
  m.formulation_warning = choice.warning;
  return m;
}

std::vector<MaterialConfig> parse_materials(const DeckReader& r, const YAML::Node& node,
                                            const Config& c) {
  r.check_list(node, "materials");
  require(node.size() > 0, r, node, "materials", "at least one material is required");
  std::vector<MaterialConfig> materials;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = item_key("materials", i);
    materials.push_back(parse_material(r, node[i], key, c));
    for (size_t j = 0; j < i; ++j)
      if (materials[j].group == materials[i].group)
        r.fail(child_key(key, "group"), node[i]["group"],
               "duplicate material group '" + materials[i].group + "' (also in " +
                   item_key("materials", j) + ")");
  }
  return materials;
}

void write_materials(YAML::Emitter& out, const std::vector<MaterialConfig>& materials,
                     const Config& c) {
  out << YAML::BeginSeq;
  for (const auto& m : materials) {
    out << YAML::BeginMap;
    write_keys(out, material_keys(), m, c);
    out << YAML::EndMap;
    out << YAML::Comment(m.law->derived_values() +
                         "; element: " + name_of(kElementFormulationNames, m.element) + " (" +
                         m.formulation_reason + ")");
  }
  out << YAML::EndSeq;
}

// A list of entries, each a map printed with `table` (flow style when empty: "[]").
template <class S>
void write_list(YAML::Emitter& out, const std::vector<S>& items, const KeyTable<S>& table,
                const Config& c) {
  if (items.empty()) out << YAML::Flow;
  out << YAML::BeginSeq;
  for (const auto& item : items) {
    out << YAML::BeginMap;
    write_keys(out, table, item, c);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

template <class S>
void write_map(YAML::Emitter& out, const KeyTable<S>& table, const S& s, const Config& c) {
  out << YAML::BeginMap;
  write_keys(out, table, s, c);
  out << YAML::EndMap;
}

// Control belongs to static and quasi-static runs: its targets are equilibria. Cavities,
// cables, states and tip run in dynamic runs too, the states as a schedule in time
// (solvers/stepping/dynamic_states_stepper.hpp).
KeyUse<Config> static_runs_only(const std::string& reason) {
  return use_when<Config>(
      [](const Config& c, const Config&) { return c.time.type != TimeType::dynamic; }, reason,
      "static and quasi-static runs only");
}

}  // namespace

// The model's own keys follow `model`, in its law's table (materials/registry.hpp): read from
// the whole map by parse_material (`model` has no reader of its own), printed after its name.
const KeyTable<MaterialConfig>& material_keys() {
  static const KeyTable<MaterialConfig> keys = {
      text_key("group", &MaterialConfig::group, "name",
               "volume physical group (unique across materials)")
          .needed(),
      custom_key<MaterialConfig>(
          "model", "name", "required",
          [] {
            std::vector<std::string> names;
            for (const auto& name : material_law_names()) names.push_back("`" + name + "`");
            return join(names) + " (docs/formulation.md); its keys are in the table below";
          }(),
          nullptr,
          [](YAML::Emitter& out, const MaterialConfig& m, const Config&) {
            out << m.law->name();
            print_material_law(out, *m.law);
          })
          .needed(),
      number_key("density", &MaterialConfig::density,
                 // Above any solid's (osmium: 22,590 kg/m^3), and far from where rho g overflows.
                 Limit{"in [0, 1e5]",
                       [](double x) {
                         if (x < 0) return "must be >= 0, got " + format_number(x);
                         if (x > 1e5) return "must be <= 1e5 kg/m^3, got " + format_number(x);
                         return std::string();
                       }},
                 "kg/m³: gravity load and, in dynamic runs, inertia (above any solid's; larger "
                 "values overflow rho g)"),
      enum_key("formulation", &MaterialConfig::formulation, kElementFormulationNames,
               "the element: `fbar` (locking-free for nearly incompressible bodies on P2 "
               "meshes), `nodal_pressure` (the same on P1 meshes, for laws with a (ln J)^2 "
               "volumetric term), `displacement`, or `auto`: at nu >= 0.49 `fbar` on P2 and "
               "`nodal_pressure` on P1 where the law allows, else `displacement`; at nu = 0.5 "
               "the same elements with volume multipliers (docs/formulation.md); the "
               "element that runs is printed beside the material"),
  };
  return keys;
}

const KeyTable<Config>& deck_section_keys() {
  using R = const DeckReader&;
  using N = const YAML::Node&;
  using K = const std::string&;
  static const KeyTable<Config> keys = {
      custom_key<Config>(
          "mesh", "map", "required", "the mesh",
          [](R r, N n, K, Config& s, const Config& c) {
            s.mesh = parse_mesh(r, n, std::filesystem::path(c.deck_path).parent_path().string(), c);
          },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_map(out, mesh_keys(), c.mesh, c);
          })
          .needed(),
      custom_key<Config>(
          "materials", "list", "required", "the materials, one per volume group",
          [](R r, N n, K, Config& s, const Config& c) { s.materials = parse_materials(r, n, c); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_materials(out, c.materials, c);
          })
          .needed(),
      custom_key<Config>(
          "boundary", "list", "none", "Dirichlet conditions",
          [](R r, N n, K key, Config& s, const Config& c) {
            r.check_list(n, key);
            for (size_t i = 0; i < n.size(); ++i)
              s.dirichlet.push_back(parse_boundary(r, n[i], item_key(key, i), c));
          },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_list(out, c.dirichlet, boundary_keys(), c);
          }),
      custom_key<Config>(
          "loads", "map", "none", "gravity, pressures and tractions",
          [](R r, N n, K, Config& s, const Config&) { parse_loads(r, n, s); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_map(out, loads_keys(), c, c);
          }),
      custom_key<Config>(
          "cavities", "list", "none", "closed surfaces that hold gas or liquid",
          [](R r, N n, K, Config& s, const Config& c) { s.cavities = parse_cavities(r, n, c); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_list(out, c.cavities, cavity_keys(), c);
          }),
      custom_key<Config>(
          "cables", "list", "none", "tendons that pull the body",
          [](R r, N n, K, Config& s, const Config& c) { s.cables = parse_cables(r, n, c); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_list(out, c.cables, cable_keys(), c);
          })
          .printed_when([](const Config& c) { return !c.cables.empty(); }),
      custom_key<Config>(
          "time", "map", "static", "load or time stepping",
          [](R r, N n, K, Config& s, const Config& c) { s.time = parse_time(r, n, c); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_map(out, time_keys(), c.time, c);
          }),
      custom_key<Config>(
          "states", "list", "one state", "the states a run goes through",
          [](R r, N n, K, Config& s, const Config& c) {
            s.states = parse_states(r, n, c);
            s.time.steps = s.states.front().steps;  // the first state's steps replace time's
          },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_list(out, c.states, state_keys(), c);
          })
          // An empty list is not a valid deck (one implicit state).
          .printed_when([](const Config& c) { return !c.states.empty(); }),
      custom_key<Config>(
          "tip", "map", "none", "a face whose inclination is reported per state",
          [](R r, N n, K key, Config& s, const Config& c) {
            TipConfig tip;
            read_keys(r, n, key, tip_keys(), tip, c);
            s.tip = tip;
          },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            out << YAML::Flow;
            write_map(out, tip_keys(), *c.tip, c);
          })
          .printed_when([](const Config& c) { return c.tip.has_value(); }),
      custom_key<Config>(
          "obstacles", "list", "none", "rigid bodies the body may touch (docs/contact.md)",
          [](R r, N n, K, Config& s, const Config& c) { s.obstacles = parse_obstacles(r, n, c); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_list(out, c.obstacles, obstacle_keys(), c);
          })
          .printed_when([](const Config& c) { return !c.obstacles.empty(); }),
      custom_key<Config>(
          "contact", "map", "none (required with obstacles)",
          "the body's surfaces that touch the obstacles or each other, the barrier "
          "(docs/contact.md)",
          [](R r, N n, K, Config& s, const Config& c) { s.contact = parse_contact(r, n, c); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_map(out, contact_keys(), c.contact, c);
          })
          .printed_when([](const Config& c) { return !c.obstacles.empty() || c.contact.self; }),
      custom_key<Config>(
          "control", "map", "none", "inverse control",
          [](R r, N n, K, Config& s, const Config& c) { s.control = parse_control(r, n, c); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_map(out, control_keys(), *c.control, c);
          })
          .only(static_runs_only(
              "control needs time.type static or quasi_static (time.type is dynamic)"))
          .printed_when([](const Config& c) { return c.control.has_value(); }),
      custom_key<Config>(
          "solver", "map", "mumps", "PETSc options",
          [](R r, N n, K, Config& s, const Config& c) { s.solver = parse_solver(r, n, c); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_map(out, solver_keys(), c.solver, c);
          }),
      custom_key<Config>(
          "output", "map", "out/<deck name>", "what is written where",
          [](R r, N n, K, Config& s, const Config& c) { s.output = parse_output(r, n, c); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_map(out, output_keys(), c.output, c);
          }),
      custom_key<Config>(
          "exact", "map", "none", "an exact solution to compare with",
          [](R r, N n, K, Config& s, const Config&) { parse_exact_section(r, n, s); },
          [](YAML::Emitter& out, const Config& c, const Config&) {
            write_map(out, exact_keys(), c.exact, c);
          }),
  };
  return keys;
}

}  // namespace hs
