#include "mesh/mesh_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "fem/element.hpp"

namespace hs {

double tet_quality(const double* a, const double* b, const double* c, const double* d) {
  const double* p[4] = {a, b, c, d};
  double edges = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      for (int k = 0; k < 3; ++k) edges += (p[i][k] - p[j][k]) * (p[i][k] - p[j][k]);
  double e[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) e[i][k] = p[i + 1][k] - a[k];
  const double six_v = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                       e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                       e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  if (edges <= 0) return 0;
  const double v = six_v / 6;  // signed: an inverted corner tetrahedron gets q < 0
  return 12 * std::cbrt(9 * v * v) * (v < 0 ? -1 : 1) / edges;
}

MeshStatistics mesh_statistics(const Mesh& mesh, const std::vector<std::string>& closed_groups) {
  MeshStatistics s;
  s.order = mesh.order;
  s.nodes = mesh.num_nodes();
  s.tets = mesh.num_tets();
  for (int k = 0; k < 3; ++k) {
    s.lower[k] = std::numeric_limits<double>::infinity();
    s.upper[k] = -s.lower[k];
  }
  for (int64_t n = 0; n < s.nodes; ++n)
    for (int k = 0; k < 3; ++k) {
      s.lower[k] = std::min(s.lower[k], mesh.x[3 * n + k]);
      s.upper[k] = std::max(s.upper[k], mesh.x[3 * n + k]);
    }
  const int npe = mesh.nodes_per_tet();
  std::vector<double> X(3 * npe);
  s.smallest_volume = std::numeric_limits<double>::infinity();
  s.worst_quality = std::numeric_limits<double>::infinity();
  for (int64_t e = 0; e < s.tets; ++e) {
    for (int a = 0; a < npe; ++a)
      for (int k = 0; k < 3; ++k) X[3 * a + k] = mesh.x[3 * mesh.tets[npe * e + a] + k];
    const double v = tet_volume(mesh.order, X.data());
    if (v < s.smallest_volume) {
      s.smallest_volume = v;
      s.smallest_tet = e;
    }
    const double q = tet_quality(&X[0], &X[3], &X[6], &X[9]);
    if (q < s.worst_quality) {
      s.worst_quality = q;
      s.worst_tet = e;
    }
  }
  const int npf = mesh.nodes_per_face();
  std::vector<double> xf(3 * npf);
  for (const auto& group : closed_groups) {
    auto it = mesh.surfaces.find(group);
    if (it == mesh.surfaces.end()) continue;
    double volume = 0;
    for (size_t f = 0; f < it->second.size() / npf; ++f) {
      for (int a = 0; a < npf; ++a)
        for (int k = 0; k < 3; ++k) xf[3 * a + k] = mesh.x[3 * it->second[npf * f + a] + k];
      volume += face_enclosed_volume(mesh.order, xf.data());
    }
    s.enclosed_volumes[group] = volume;
  }
  return s;
}

std::string format_statistics(const MeshStatistics& s) {
  std::ostringstream o;
  o.precision(4);
  o << "nodes " << s.nodes << ", tetrahedra " << s.tets << " (P" << s.order << "), dofs "
    << 3 * s.nodes << "\n";
  o << "bounding box [" << s.lower[0] << ", " << s.upper[0] << "] x [" << s.lower[1] << ", "
    << s.upper[1] << "] x [" << s.lower[2] << ", " << s.upper[2] << "] m\n";
  if (s.tets > 0) {
    o << "smallest tetrahedron " << s.smallest_tet << ": volume " << s.smallest_volume << " m^3\n";
    o << "worst-shaped tetrahedron " << s.worst_tet << ": mean ratio " << s.worst_quality
      << " (1 is regular)\n";
  }
  for (const auto& [group, volume] : s.enclosed_volumes)
    o << "surface '" << group << "' encloses " << volume << " m^3 (" << volume * 1e6 << " ml)\n";
  return o.str();
}

}  // namespace hs
