#include "mesh/mesh.hpp"

namespace hs {

MeshGroups groups_of(const Mesh& mesh) {
  MeshGroups g;
  g.volumes = mesh.volume_names;
  for (const auto& [name, faces] : mesh.surfaces)
    g.surface_faces[name] = static_cast<int64_t>(faces.size()) / mesh.nodes_per_face();
  for (const auto& [name, nodes] : mesh.node_groups)
    g.group_nodes[name] = static_cast<int64_t>(nodes.size());
  return g;
}

}  // namespace hs
