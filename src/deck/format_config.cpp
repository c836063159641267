// format_config: the resolved Config as a deck. The text is itself a valid deck that
// parse_deck reads back to the same Config (tests/deck), so a run can be repeated from
// its printed configuration. Keys that the configuration does not use (e.g. time.dt of a
// static run) are left out, as parse_deck would refuse them.
#include <yaml-cpp/yaml.h>

#include <filesystem>

#include "common/deck_reader.hpp"
#include "deck/deck.hpp"
#include "deck/section_keys.hpp"
#include "materials/material.hpp"
#include "verification/registry.hpp"

namespace hs {
namespace {

// Numbers as their shortest exact text, so that printing loses nothing.
void emit_numbers(YAML::Emitter& out, const std::string& key, const double* values, size_t n) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (size_t i = 0; i < n; ++i) out << format_number(values[i]);
  out << YAML::EndSeq;
}

void emit_number(YAML::Emitter& out, const std::string& key, double value) {
  out << YAML::Key << key << YAML::Value << format_number(value);
}

void emit_number_map(YAML::Emitter& out, const std::string& key,
                     const std::map<std::string, double>& values) {
  out << YAML::Key << key << YAML::Value << YAML::Flow << YAML::BeginMap;
  for (const auto& [name, value] : values) emit_number(out, name, value);
  out << YAML::EndMap;
}

void emit_materials(YAML::Emitter& out, const std::vector<MaterialConfig>& materials) {
  out << YAML::Key << "materials" << YAML::Value << YAML::BeginSeq;
  for (const auto& m : materials) {
    out << YAML::BeginMap;
    out << YAML::Key << "group" << YAML::Value << m.group;
    out << YAML::Key << "model" << YAML::Value << m.law->name();
    m.law->print(out);
    emit_number(out, "density", m.density);
    out << YAML::EndMap;
    out << YAML::Comment(m.law->derived_values());
  }
  out << YAML::EndSeq;
}

void emit_boundary(YAML::Emitter& out, const Config& c) {
  out << YAML::Key << "boundary" << YAML::Value;
  if (c.dirichlet.empty()) out << YAML::Flow;
  out << YAML::BeginSeq;
  for (const auto& bc : c.dirichlet) {
    out << YAML::BeginMap;
    write_keys(out, boundary_keys(), bc, c);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

void emit_cavities(YAML::Emitter& out, const Config& c) {
  out << YAML::Key << "cavities" << YAML::Value;
  if (c.cavities.empty()) out << YAML::Flow;
  out << YAML::BeginSeq;
  for (const auto& cavity : c.cavities) {
    out << YAML::BeginMap;
    write_keys(out, cavity_keys(), cavity, c);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

void emit_cables(YAML::Emitter& out, const Config& c) {
  out << YAML::Key << "cables" << YAML::Value << YAML::BeginSeq;
  for (const auto& cable : c.cables) {
    out << YAML::BeginMap;
    write_keys(out, cable_keys(), cable, c);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

// Only when the deck gave states: an empty list is not a valid deck (one implicit state).
void emit_states(YAML::Emitter& out, const Config& c) {
  if (c.states.empty()) return;
  out << YAML::Key << "states" << YAML::Value << YAML::BeginSeq;
  for (const auto& s : c.states) {
    out << YAML::BeginMap;
    write_keys(out, state_keys(), s, c);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
}

// Only the bounds the deck set: an unset bound keeps its default (no bound), which is not
// worth printing (and 1e300 would read as a bound the deck never gave).
void emit_bound(YAML::Emitter& out, const std::string& key, double value, double unset) {
  if (value != unset) emit_number(out, key, value);
}

constexpr const char* kCavityKeys[] = {"cavity",
                                       "min_pressure",
                                       "max_pressure",
                                       "min_volume_growth",
                                       "max_volume_growth",
                                       "max_pressure_change"};
constexpr const char* kCableKeys[] = {"cable",    "min_force", "max_force",
                                      "min_pull", "max_pull",  "max_force_change"};

void emit_control(YAML::Emitter& out, const ControlConfig& control,
                  const std::vector<CableConfig>& cables) {
  const ActuatorConfig unset;
  out << YAML::Key << "control" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "effectors" << YAML::Value << YAML::BeginSeq;
  for (const auto& e : control.effectors) {
    out << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << e.name;
    if (e.point.empty())
      emit_numbers(out, "position", e.position.data(), 3);
    else
      out << YAML::Key << "point" << YAML::Value << e.point;
    out << YAML::Key << "directions" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (int d = 0; d < 3; ++d)
      if (e.directions[d]) out << std::string(1, static_cast<char>('x' + d));
    out << YAML::EndSeq;
    emit_number(out, "weight", e.weight);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "actuators" << YAML::Value << YAML::BeginSeq;
  for (const auto& a : control.actuators) {
    out << YAML::BeginMap;
    const bool cable = std::any_of(cables.begin(), cables.end(),
                                   [&](const CableConfig& c) { return c.name == a.constraint; });
    // The deck's keys in the driven constraint's units: a cable's force and pull, a cavity's
    // pressure and volume growth. A cable's min_force is always printed (its default is 0).
    const char* const* k = cable ? kCableKeys : kCavityKeys;
    out << YAML::Key << k[0] << YAML::Value << a.constraint;
    if (cable)
      emit_number(out, k[1], a.min_multiplier);
    else
      emit_bound(out, k[1], a.min_multiplier, unset.min_multiplier);
    emit_bound(out, k[2], a.max_multiplier, unset.max_multiplier);
    emit_bound(out, k[3], a.min_measure_change, unset.min_measure_change);
    emit_bound(out, k[4], a.max_measure_change, unset.max_measure_change);
    emit_bound(out, k[5], a.max_multiplier_step, unset.max_multiplier_step);
    out << YAML::EndMap;
  }
  out << YAML::EndSeq;
  // Only when the deck gave targets: an empty list is not a valid deck.
  if (!control.targets.empty()) {
    out << YAML::Key << "targets" << YAML::Value << YAML::BeginSeq;
    for (const auto& set : control.targets) {
      out << YAML::Flow << YAML::BeginMap;
      for (const auto& t : set) emit_numbers(out, t.effector, t.position.data(), 3);
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  out << YAML::Key << "steps_per_target" << YAML::Value << control.steps_per_target;
  emit_number(out, "regularization", control.regularization);
  out << YAML::Key << "newton_finish" << YAML::Value << control.newton_finish;
  out << YAML::Key << "free_solve" << YAML::Value << name_of(kFreeSolveNames, control.free_solve);
  out << YAML::Key << "refactor_every" << YAML::Value << control.refactor_every;
  out << YAML::Key << "check_equilibrium" << YAML::Value << control.check_equilibrium;
  out << YAML::Key << "factor_threads" << YAML::Value << control.factor_threads;
  out << YAML::EndMap;
}

}  // namespace

std::string format_config(const Config& c) {
  YAML::Emitter out;
  out << YAML::Comment("deck: " + c.deck_path);
  out << YAML::BeginMap;
  out << YAML::Key << "mesh" << YAML::Value << YAML::BeginMap;
  write_keys(out, mesh_keys(), c.mesh, c);
  out << YAML::EndMap;
  emit_materials(out, c.materials);
  emit_boundary(out, c);
  out << YAML::Key << "loads" << YAML::Value << YAML::BeginMap;
  write_keys(out, loads_keys(), c, c);
  out << YAML::EndMap;
  // Cavities, states and tip belong to static and quasi-static runs only.
  if (c.time.type != TimeType::dynamic) emit_cavities(out, c);
  if (!c.cables.empty()) emit_cables(out, c);
  out << YAML::Key << "time" << YAML::Value << YAML::BeginMap;
  write_keys(out, time_keys(), c.time, c);
  out << YAML::EndMap;
  emit_states(out, c);
  if (c.tip) {
    out << YAML::Key << "tip" << YAML::Value << YAML::Flow << YAML::BeginMap;
    write_keys(out, tip_keys(), *c.tip, c);
    out << YAML::EndMap;
  }
  if (c.control) emit_control(out, *c.control, c.cables);

  out << YAML::Key << "solver" << YAML::Value << YAML::BeginMap;
  write_keys(out, solver_keys(), c.solver, c);
  out << YAML::EndMap;
  out << YAML::Key << "output" << YAML::Value << YAML::BeginMap;
  write_keys(out, output_keys(), c.output, c);
  out << YAML::EndMap;

  out << YAML::Key << "exact" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "type" << YAML::Value << (c.exact.type ? c.exact.type->name : "none");
  emit_number_map(out, "parameters", c.exact.parameters);
  out << YAML::EndMap;

  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace hs
