// The column method needs a closed surface: along every column the floors and ceilings pair up
// only if each edge joins exactly two triangles that use it in opposite directions.
#include <algorithm>
#include <cstdint>
#include <sstream>
#include <vector>

#include "fluidweight/fluidweight.hpp"

namespace fluidweight {
namespace {

struct EdgeUse {
  uint64_t key;  // smaller vertex << 32 | larger vertex
  int position;  // 3 * triangle + edge: the order in which the edge first appears
  bool forward;  // used from the smaller to the larger vertex
};

constexpr size_t kTrianglesNamed = 8;  // of an edge shared by more than two

}  // namespace

void check_closed_surface(const SurfaceMesh& mesh, const std::string& name) {
  const int nv = mesh.num_vertices(), nt = mesh.num_triangles();
  if (mesh.vertices.size() % 3 != 0 || mesh.triangles.size() % 3 != 0) {
    throw InputError(name + ": vertex or triangle arrays are not multiples of 3");
  }
  if (nt == 0) throw InputError(name + ": the surface has no triangles");
  std::vector<EdgeUse> uses;
  uses.reserve(3 * static_cast<size_t>(nt));
  for (int t = 0; t < nt; ++t) {
    const int* v = &mesh.triangles[3 * t];
    for (int k = 0; k < 3; ++k) {
      if (v[k] < 0 || v[k] >= nv) {
        std::ostringstream msg;
        msg << name << ": triangle " << t << " has vertex index " << v[k] << ", outside [0, " << nv
            << ")";
        throw InputError(msg.str());
      }
    }
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) {
      std::ostringstream msg;
      msg << name << ": triangle " << t << " repeats a vertex (" << v[0] << ", " << v[1] << ", "
          << v[2] << ")";
      throw InputError(msg.str());
    }
    for (int k = 0; k < 3; ++k) {
      uint32_t a = static_cast<uint32_t>(v[k]), b = static_cast<uint32_t>(v[(k + 1) % 3]);
      uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      uses.push_back(EdgeUse{key, 3 * t + k, a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.key < y.key || (x.key == y.key && x.position < y.position);
  });
  // Among the bad edges, report the one that appears first in triangle order.
  int bad_position = -1;
  std::string reason;
  for (size_t first = 0; first < uses.size();) {
    size_t end = first;
    while (end < uses.size() && uses[end].key == uses[first].key) ++end;
    size_t count = end - first;
    bool bad = count != 2 || uses[first].forward == uses[first + 1].forward;
    if (bad && (bad_position < 0 || uses[first].position < bad_position)) {
      bad_position = uses[first].position;
      std::ostringstream why;
      if (count == 1) {
        why << "is used by triangle " << uses[first].position / 3
            << " only: the surface is open there";
      } else if (count > 2) {
        // The first few triangles name the place; a surface of one edge shared a million times
        // made this message a line of megabytes.
        const size_t shown = std::min<size_t>(count, kTrianglesNamed);
        why << "is shared by " << count << " triangles (";
        for (size_t u = first; u < first + shown; ++u)
          why << (u > first ? ", " : "") << uses[u].position / 3;
        if (shown < count) why << ", ...";
        why << "): the surface is not manifold there";
      } else {
        why << "is used in the same direction by triangles " << uses[first].position / 3 << " and "
            << uses[first + 1].position / 3 << ": their orientations disagree (flip one)";
      }
      reason = why.str();
    }
    first = end;
  }
  if (bad_position >= 0) {
    int t = bad_position / 3, k = bad_position % 3;
    std::ostringstream msg;
    msg << name << ": not a closed surface: edge (" << mesh.triangles[3 * t + k] << ", "
        << mesh.triangles[3 * t + (k + 1) % 3] << ") " << reason;
    throw InputError(msg.str());
  }
}

}  // namespace fluidweight
