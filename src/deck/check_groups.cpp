// check_groups: the deck's group names against the mesh, before any assembly.
#include <algorithm>

#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "deck/deck.hpp"

namespace hs {
namespace {

bool has_nodes(const MeshGroups& mesh, const std::string& group) {
  const auto it = mesh.group_nodes.find(group);
  return it != mesh.group_nodes.end() && it->second > 0;
}

bool is_volume(const MeshGroups& mesh, const std::string& group) {
  return std::find(mesh.volumes.begin(), mesh.volumes.end(), group) != mesh.volumes.end();
}

bool is_surface(const MeshGroups& mesh, const std::string& group) {
  const auto it = mesh.surface_faces.find(group);
  return it != mesh.surface_faces.end() && it->second > 0;
}

// "volumes: body; surfaces: inner, outer; other groups: tip".
std::string listing(const MeshGroups& mesh) {
  std::vector<std::string> surfaces, others;
  for (const auto& [name, faces] : mesh.surface_faces) surfaces.push_back(name);
  for (const auto& [name, nodes] : mesh.group_nodes)
    if (!is_volume(mesh, name) && !mesh.surface_faces.count(name)) others.push_back(name);
  auto names = [](const std::vector<std::string>& v) { return v.empty() ? "none" : join(v); };
  return "volumes: " + names(mesh.volumes) + "; surfaces: " + names(surfaces) +
         "; other groups: " + names(others);
}

}  // namespace

void check_groups(const Config& c, const MeshGroups& mesh) {
  auto fail = [&](const std::string& key, const std::string& reason) {
    throw InputError(printable(c.deck_path + ": " + key + ": " + reason + " (mesh " + c.mesh.file +
                               " has " + listing(mesh) + ")"));
  };
  // Every group must carry nodes: an empty one would silently constrain or load nothing.
  auto require_nodes = [&](const std::string& key, const std::string& group) {
    if (!mesh.group_nodes.count(group)) fail(key, "group '" + group + "' is not in the mesh");
    if (!has_nodes(mesh, group)) fail(key, "group '" + group + "' has no nodes");
  };

  for (size_t i = 0; i < c.materials.size(); ++i) {
    const std::string key = child_key(item_key("materials", i), "group"),
                      group = c.materials[i].group;
    require_nodes(key, group);
    if (!is_volume(mesh, group)) fail(key, "group '" + group + "' is not a volume");
  }
  for (const auto& volume : mesh.volumes) {
    const bool assigned = std::any_of(c.materials.begin(), c.materials.end(),
                                      [&](const MaterialConfig& m) { return m.group == volume; });
    if (!assigned) fail("materials", "volume '" + volume + "' of the mesh has no material");
  }
  for (size_t i = 0; i < c.dirichlet.size(); ++i)
    require_nodes(child_key(item_key("boundary", i), "group"), c.dirichlet[i].group);
  for (size_t i = 0; i < c.pressures.size(); ++i) {
    const std::string key = child_key(item_key("loads.pressure", i), "group");
    const std::string group = c.pressures[i].group;
    require_nodes(key, group);
    if (!is_surface(mesh, group)) fail(key, "group '" + group + "' is not a surface");
  }
  for (size_t i = 0; i < c.tractions.size(); ++i) {
    const std::string key = child_key(item_key("loads.traction", i), "group");
    const std::string group = c.tractions[i].group;
    require_nodes(key, group);
    if (!is_surface(mesh, group)) fail(key, "group '" + group + "' is not a surface");
  }
  // A cavity is a closed surface of boundary faces; the tip's inclination is that of faces.
  for (size_t i = 0; i < c.cavities.size(); ++i) {
    const std::string key = child_key(item_key("cavities", i), "group");
    const std::string group = c.cavities[i].group;
    require_nodes(key, group);
    if (!is_surface(mesh, group)) fail(key, "group '" + group + "' is not a surface");
  }
  for (size_t i = 0; i < c.contact.surfaces.size(); ++i) {
    const std::string key = item_key("contact.surfaces", i), group = c.contact.surfaces[i];
    require_nodes(key, group);
    if (!is_surface(mesh, group)) fail(key, "group '" + group + "' is not a surface");
  }
  if (c.tip) {
    require_nodes("tip.group", c.tip->group);
    if (!is_surface(mesh, c.tip->group))
      fail("tip.group", "group '" + c.tip->group + "' is not a surface");
  }
  // An effector given as a point group follows that group's one node.
  if (c.control)
    for (size_t i = 0; i < c.control->effectors.size(); ++i) {
      const std::string key = child_key(item_key("control.effectors", i), "point");
      const std::string group = c.control->effectors[i].point;
      if (group.empty()) continue;  // a material point (position), located by the solver
      require_nodes(key, group);
      const int64_t n = mesh.group_nodes.at(group);
      if (n != 1)
        fail(key, "group '" + group + "' has " + std::to_string(n) +
                      " nodes, an effector point needs exactly one");
    }
}

}  // namespace hs
