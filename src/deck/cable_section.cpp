#include "deck/cable_section.hpp"

#include <cmath>

#include "deck/section_keys.hpp"

namespace hs {
namespace {

CableConfig parse_cable(const DeckReader& r, const YAML::Node& node, const std::string& key,
                        const Config& c) {
  CableConfig cable;
  read_keys(r, node, key, cable_keys(), cable, c);
  const std::string pkey = child_key(key, "points");
  const YAML::Node points = node["points"];
  const size_t segments = cable.points.size() - (cable.pull_point ? 0 : 1);
  require(!cable.points.empty() && segments >= 1, r, points, pkey,
          "a cable needs at least two points, or one point and a pull_point (got " +
              std::to_string(cable.points.size()) + " points" +
              (cable.pull_point ? "" : " and no pull_point") + ")");
  // Every segment must have a length: its direction is the direction of the pull.
  std::vector<std::array<double, 3>> path = cable.points;
  if (cable.pull_point) path.push_back(*cable.pull_point);
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    const double d = std::hypot(path[i + 1][0] - path[i][0], path[i + 1][1] - path[i][1],
                                path[i + 1][2] - path[i][2]);
    if (!(d > 0))
      r.fail(i + 1 < cable.points.size() ? item_key(pkey, i + 1) : child_key(key, "pull_point"),
             i + 1 < cable.points.size() ? points[i + 1] : node["pull_point"],
             "coincides with the point before it: a cable segment needs a length");
  }
  return cable;
}

}  // namespace

const KeyTable<CableConfig>& cable_keys() {
  static const KeyTable<CableConfig> keys = {
      text_key("name", &CableConfig::name, "name",
               "unique among cables and cavities; control actuators name it")
          .needed(),
      custom_key<CableConfig>(
          "points", "list of 3 numbers", "required",
          "material points of the undeformed body (m) the cable runs through, in order (each "
          "located in its tetrahedron: a point outside the mesh is an error); at least two, or "
          "one with a `pull_point`; consecutive points distinct",
          [](const DeckReader& r, const YAML::Node& points, const std::string& key,
             CableConfig& cable, const Config&) {
            r.check_list(points, key);
            for (size_t i = 0; i < points.size(); ++i)
              cable.points.push_back(r.vector3(points[i], item_key(key, i)));
          },
          [](YAML::Emitter& out, const CableConfig& cable, const Config&) {
            // The emitter's own digits, not format_number's (both read back exactly): the
            // printout is the restart fingerprint, which a change of spelling would break.
            out << YAML::BeginSeq;
            for (const auto& p : cable.points) {
              out << YAML::Flow << YAML::BeginSeq;
              for (double x : p) out << x;
              out << YAML::EndSeq;
            }
            out << YAML::EndSeq;
          })
          .needed(),
      custom_key<CableConfig>(
          "pull_point", "3 numbers", "none",
          "a point fixed in space after the last point: the cable's last segment runs to it",
          [](const DeckReader& r, const YAML::Node& n, const std::string& key, CableConfig& cable,
             const Config&) { cable.pull_point = r.vector3(n, key); },
          [](YAML::Emitter& out, const CableConfig& cable, const Config&) {
            write_numbers(out, cable.pull_point->data(), 3);
          })
          .printed_when([](const CableConfig& cable) { return cable.pull_point.has_value(); }),
      number_key("force", &CableConfig::force, at_least(0, "a cable pulls, it cannot push"),
                 "tension (N) at the end of the first state, ramped with the load factor like a "
                 "cavity pressure; later states keep it (they do not name cables)"),
      number_key("friction", &CableConfig::friction, at_least(0, "a Coulomb friction coefficient"),
                 "Coulomb friction coefficient where the cable turns through its points (the "
                 "capstan equation, docs/control.md): the tension falls by exp(-friction theta) "
                 "at each turn away from the motor; 0 is the frictionless cable. With friction "
                 "the tangent is not symmetric (LU, not Cholesky)"),
  };
  return keys;
}

std::vector<CableConfig> parse_cables(const DeckReader& r, const YAML::Node& node,
                                      const Config& c) {
  r.check_list(node, "cables");
  std::vector<CableConfig> cables;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = item_key("cables", i);
    cables.push_back(parse_cable(r, node[i], key, c));
    const std::string& name = cables.back().name;
    for (size_t j = 0; j < i; ++j)
      if (cables[j].name == name)
        r.fail(child_key(key, "name"), node[i]["name"],
               "duplicate cable name '" + name + "' (also " + item_key("cables", j) + ")");
    for (const auto& cavity : c.cavities)
      if (cavity.group == name)
        r.fail(child_key(key, "name"), node[i]["name"],
               "'" + name + "' is also a cavity's name: actuators are named by it");
  }
  return cables;
}

}  // namespace hs
