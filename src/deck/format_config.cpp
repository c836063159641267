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
  if (c.control) {
    out << YAML::Key << "control" << YAML::Value << YAML::BeginMap;
    write_keys(out, control_keys(), *c.control, c);
    out << YAML::EndMap;
  }

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
