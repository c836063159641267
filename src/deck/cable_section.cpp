#include "deck/cable_section.hpp"

#include <cmath>

namespace hs {
namespace {

CableConfig parse_cable(const DeckReader& r, const YAML::Node& node, const std::string& key) {
  r.check_map(node, key, {"name", "points", "pull_point", "force", "friction"});
  CableConfig cable;
  cable.name = r.text(required(r, node, key, "name"), child_key(key, "name"));
  const std::string pkey = child_key(key, "points");
  const YAML::Node points = required(r, node, key, "points");
  r.check_list(points, pkey);
  for (size_t i = 0; i < points.size(); ++i)
    cable.points.push_back(r.vector3(points[i], item_key(pkey, i)));
  if (const auto n = node["pull_point"])
    cable.pull_point = r.vector3(n, child_key(key, "pull_point"));
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
  if (const auto n = node["force"]) {
    cable.force = r.number(n, child_key(key, "force"));
    require(cable.force >= 0, r, n, child_key(key, "force"),
            "must be >= 0 (a cable pulls, it cannot push), got " + format_number(cable.force));
  }
  if (const auto n = node["friction"]) {
    cable.friction = r.number(n, child_key(key, "friction"));
    require(cable.friction >= 0, r, n, child_key(key, "friction"),
            "must be >= 0 (a Coulomb friction coefficient), got " + format_number(cable.friction));
  }
  return cable;
}

}  // namespace

void parse_cable_section(const DeckReader& r, const YAML::Node& root, Config& c) {
  const YAML::Node node = root["cables"];
  if (!node) return;
  if (c.time.type == TimeType::dynamic)
    forbid(r, root, "", "cables", "cables need time.type static or quasi_static");
  r.check_list(node, "cables");
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string key = item_key("cables", i);
    c.cables.push_back(parse_cable(r, node[i], key));
    const std::string& name = c.cables.back().name;
    for (size_t j = 0; j < i; ++j)
      if (c.cables[j].name == name)
        r.fail(child_key(key, "name"), node[i]["name"],
               "duplicate cable name '" + name + "' (also " + item_key("cables", j) + ")");
    for (const auto& cavity : c.cavities)
      if (cavity.group == name)
        r.fail(child_key(key, "name"), node[i]["name"],
               "'" + name + "' is also a cavity's name: actuators are named by it");
  }
}

}  // namespace hs
