#include "deck/deck_keys.hpp"

#include "deck/section_keys.hpp"
#include "materials/registry.hpp"

namespace hs {

void write_numbers(YAML::Emitter& out, const double* values, size_t n) {
  out << YAML::Flow << YAML::BeginSeq;
  for (size_t i = 0; i < n; ++i) out << format_number(values[i]);
  out << YAML::EndSeq;
}

void write_axes(YAML::Emitter& out, const std::array<bool, 3>& on) {
  out << YAML::Flow << YAML::BeginSeq;
  for (int d = 0; d < 3; ++d)
    if (on[d]) out << std::string(1, static_cast<char>('x' + d));
  out << YAML::EndSeq;
}

std::array<bool, 3> read_axes(const DeckReader& r, const YAML::Node& n, const std::string& key,
                              const std::string& what) {
  r.check_list(n, key);
  require(n.size() > 0, r, n, key, "must name at least one of x, y, z");
  std::array<bool, 3> on{false, false, false};
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string axis = one_of(r, n[i], item_key(key, i), {"x", "y", "z"});
    bool& flag = on[axis[0] - 'x'];
    require(!flag, r, n[i], item_key(key, i), what + " '" + axis + "' named twice");
    flag = true;
  }
  return on;
}

std::vector<DeckKeyTable> deck_key_tables() {
  return {
      {"mesh", markdown_table(mesh_keys())},
      {"materials", markdown_table(material_keys())},
      {"material_laws", material_laws_markdown()},
      {"boundary", markdown_table(boundary_keys())},
      {"loads", markdown_table(loads_keys())},
      {"time", markdown_table(time_keys())},
      {"cavities", markdown_table(cavity_keys())},
      {"fluid_weight", markdown_table(fluid_weight_keys())},
      {"states", markdown_table(state_keys())},
      {"cables", markdown_table(cable_keys())},
      {"obstacles", markdown_table(obstacle_keys())},
      {"contact", markdown_table(contact_keys())},
      {"control", markdown_table(control_keys())},
      {"effectors", markdown_table(effector_keys())},
      {"actuators", markdown_table(cavity_actuator_keys())},
      {"cable_actuators", markdown_table(cable_actuator_keys())},
      {"solver", markdown_table(solver_keys())},
      {"output", markdown_table(output_keys())},
      {"exact", markdown_table(exact_keys())},
  };
}

}  // namespace hs
