#include "mesh/gmsh_model.hpp"

#include <gmsh.h>

#include <algorithm>
#include <unordered_map>

#include "common/error.hpp"
#include "mesh/gmsh_process.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_faces.hpp"

namespace hs {
namespace {

constexpr int kTet4 = 4, kTet10 = 11;  // gmsh element types
const char* const kDefaultVolume = "body";

struct Group {
  int dim = 0, tag = 0;
  std::string name;
};

std::string group_label(int dim, int tag) {
  return "physical group of dimension " + std::to_string(dim) + " with tag " + std::to_string(tag);
}

// The physical groups of the model; each must have a name, unique over all dimensions
// (the mesh keys node groups by name only).
std::vector<Group> named_groups(const std::string& file) {
  gmsh::vectorpair dim_tags;
  gmsh::model::getPhysicalGroups(dim_tags);
  std::vector<Group> groups;
  for (const auto& [dim, tag] : dim_tags) {
    Group g{dim, tag, {}};
    gmsh::model::getPhysicalName(dim, tag, g.name);
    if (g.name.empty())
      throw InputError(file + ": the " + group_label(dim, tag) +
                       " has no name (hydrosoft refers to groups by name)");
    for (const auto& other : groups)
      if (other.name == g.name)
        throw InputError(file + ": two physical groups are named '" + g.name + "' (the " +
                         group_label(other.dim, other.tag) + " and the " + group_label(dim, tag) +
                         ")");
    groups.push_back(g);
  }
  return groups;
}

std::string element_name(int type) {
  std::string name;
  int dim, order, num_nodes, num_primary;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(type, name, dim, order, num_nodes, local, num_primary);
  return name;
}

// Compact numbering: gmsh node tag -> index among the nodes of tetrahedra, in tag order.
class NodeNumbering {
 public:
  explicit NodeNumbering(std::vector<size_t> tags) {
    std::sort(tags.begin(), tags.end());
    tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
    index_.reserve(tags.size());
    for (size_t i = 0; i < tags.size(); ++i) index_.emplace(tags[i], static_cast<int64_t>(i));
    tags_ = std::move(tags);
  }
  // -1 when the node belongs to no tetrahedron.
  int64_t operator()(size_t tag) const {
    const auto it = index_.find(tag);
    return it == index_.end() ? -1 : it->second;
  }
  const std::vector<size_t>& tags() const { return tags_; }

 private:
  std::vector<size_t> tags_;
  std::unordered_map<size_t, int64_t> index_;
};

// The tetrahedra of every volume entity, with their volume group. Fills mesh.volume_names,
// mesh.tet_volume and tet_tags (their element tags) and returns the gmsh node tags of the
// tetrahedra (nodes_per_tet each).
std::vector<size_t> read_tets(Mesh& mesh, const std::vector<Group>& groups, const std::string& file,
                              std::vector<size_t>& tet_tags) {
  check_tetrahedra_only(file);
  std::map<int, int> volume_of_tag;  // physical tag -> index into volume_names
  for (const auto& g : groups)
    if (g.dim == 3) {
      volume_of_tag[g.tag] = static_cast<int>(mesh.volume_names.size());
      mesh.volume_names.push_back(g.name);
    }
  const bool default_volume = mesh.volume_names.empty();
  if (default_volume) mesh.volume_names.push_back(kDefaultVolume);

  const int type = mesh.order == 1 ? kTet4 : kTet10;
  std::vector<size_t> node_tags;
  gmsh::vectorpair entities;
  gmsh::model::getEntities(entities, 3);
  for (const auto& [dim, entity] : entities) {
    std::vector<size_t> element_tags, nodes;
    gmsh::model::mesh::getElementsByType(type, element_tags, nodes, entity);
    if (element_tags.empty()) continue;
    int volume = 0;
    if (!default_volume) {
      std::vector<int> physical;
      gmsh::model::getPhysicalGroupsForEntity(dim, entity, physical);
      const std::string where =
          file + ": the tetrahedra of volume entity " + std::to_string(entity);
      if (physical.empty())
        throw InputError(where + " are in no named volume group (every volume needs one)");
      if (physical.size() > 1)
        throw InputError(where + " are in two volume groups, '" +
                         mesh.volume_names[volume_of_tag.at(physical[0])] + "' and '" +
                         mesh.volume_names[volume_of_tag.at(physical[1])] + "'");
      volume = volume_of_tag.at(physical[0]);
    }
    mesh.tet_volume.insert(mesh.tet_volume.end(), element_tags.size(), volume);
    tet_tags.insert(tet_tags.end(), element_tags.begin(), element_tags.end());
    node_tags.insert(node_tags.end(), nodes.begin(), nodes.end());
  }
  if (node_tags.empty()) throw InputError(file + ": the mesh contains no tetrahedra");
  return node_tags;
}

// Reference coordinates of the numbered nodes.
std::vector<double> read_coordinates(const NodeNumbering& numbering) {
  std::vector<size_t> tags;
  std::vector<double> coord, parametric;
  gmsh::model::mesh::getNodes(tags, coord, parametric, -1, -1, false, false);
  std::vector<double> x(3 * numbering.tags().size());
  for (size_t i = 0; i < tags.size(); ++i) {
    const int64_t n = numbering(tags[i]);
    if (n >= 0) std::copy(&coord[3 * i], &coord[3 * i + 3], &x[3 * n]);
  }
  return x;
}

// The vertices (3 per triangle, compact ids) of the triangles of a surface group.
std::vector<int64_t> group_triangles(const Group& g, const NodeNumbering& numbering,
                                     const std::string& file) {
  std::vector<int> entities;
  gmsh::model::getEntitiesForPhysicalGroup(g.dim, g.tag, entities);
  std::vector<int64_t> vertices;
  for (int entity : entities) {
    std::vector<int> types;
    gmsh::model::mesh::getElementTypes(types, 2, entity);
    for (int type : types) {
      std::string name;
      int dim, order, num_nodes, num_primary;
      std::vector<double> local;
      gmsh::model::mesh::getElementProperties(type, name, dim, order, num_nodes, local,
                                              num_primary);
      if (num_primary != 3)
        throw InputError(file + ": surface group '" + g.name + "' contains '" + name +
                         "' elements; only triangles can bound tetrahedra");
      std::vector<size_t> element_tags, nodes;
      gmsh::model::mesh::getElementsByType(type, element_tags, nodes, entity);
      for (size_t e = 0; e < element_tags.size(); ++e)
        for (int k = 0; k < 3; ++k) {
          const int64_t n = numbering(nodes[e * num_nodes + k]);
          if (n < 0)
            throw InputError(file + ": surface group '" + g.name +
                             "' has a triangle that bounds no tetrahedron");
          vertices.push_back(n);
        }
    }
  }
  return vertices;
}

std::vector<int64_t> group_nodes(const Group& g, const NodeNumbering& numbering,
                                 const std::string& file) {
  std::vector<size_t> tags;
  std::vector<double> coord;
  gmsh::model::mesh::getNodesForPhysicalGroup(g.dim, g.tag, tags, coord);
  std::vector<int64_t> nodes;
  nodes.reserve(tags.size());
  for (size_t tag : tags) {
    const int64_t n = numbering(tag);
    if (n < 0)
      throw InputError(file + ": group '" + g.name + "' has a node (tag " + std::to_string(tag) +
                       ") that belongs to no tetrahedron");
    nodes.push_back(n);
  }
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

}  // namespace

void check_tetrahedra_only(const std::string& file) {
  std::vector<int> types;
  gmsh::model::mesh::getElementTypes(types, 3);
  for (int type : types)
    if (type != kTet4 && type != kTet10)
      throw InputError(file + ": unsupported 3D element type '" + element_name(type) +
                       "' (hydrosoft meshes are tetrahedra only)");
}

Mesh mesh_from_gmsh_model(const std::string& file, int order) {
  Mesh mesh;
  mesh.order = order;
  const std::vector<Group> groups = named_groups(file);
  MeshLabels labels;
  const std::vector<size_t> tet_nodes = read_tets(mesh, groups, file, labels.tet_tags);
  const NodeNumbering numbering(tet_nodes);
  labels.node_tags = numbering.tags();
  mesh.x = read_coordinates(numbering);
  mesh.tets.resize(tet_nodes.size());
  for (size_t i = 0; i < tet_nodes.size(); ++i) mesh.tets[i] = numbering(tet_nodes[i]);
  // Bad meshes stop here, naming the node or element, before any work is done with them.
  check_finite_coordinates(mesh, file, labels);
  orient_tets_positively(mesh, file, &labels);
  check_curved_tets(mesh, file, labels);
  check_duplicate_nodes(mesh, file, labels);

  const FaceIndex faces(mesh);
  check_no_overlap(mesh, faces, file, labels);
  if (const std::string warning = quality_warning(mesh, file, labels); !warning.empty())
    tell_user("hydrosoft: warning: " + warning);
  for (const auto& g : groups) {
    if (g.dim == 2) attach_surface(mesh, faces, g.name, group_triangles(g, numbering, file), file);
    mesh.node_groups[g.name] = group_nodes(g, numbering, file);
  }
  const bool default_volume =
      std::none_of(groups.begin(), groups.end(), [](const Group& g) { return g.dim == 3; });
  if (default_volume) {
    if (mesh.node_groups.count(kDefaultVolume))
      throw InputError(file + ": the mesh has no volume group, and the default volume name '" +
                       std::string(kDefaultVolume) + "' is taken by another group");
    std::vector<int64_t>& all = mesh.node_groups[kDefaultVolume];
    all.resize(mesh.num_nodes());
    for (int64_t n = 0; n < mesh.num_nodes(); ++n) all[n] = n;
  }
  return mesh;
}

}  // namespace hs
