// The checks of a loaded mesh (mesh_checks.hpp): coordinates, P2 Jacobians, duplicated nodes,
// overlapping tetrahedra, and the quality and units warnings.
#include "mesh/mesh_checks.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <sstream>

#include "common/error.hpp"
#include "fem/element.hpp"
#include "fem/quadrature.hpp"
#include "fem/shape.hpp"
#include "mesh/mesh_statistics.hpp"
#include "mesh/tet_numbering.hpp"

namespace hs {
namespace {

using tet::node_x;

std::string point(const Mesh& mesh, int64_t n) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << mesh.x[3 * n] << ", " << mesh.x[3 * n + 1] << ", " << mesh.x[3 * n + 2] << ")";
  return s.str();
}

// Whether every edge node of P2 tetrahedron t sits at its edge's midpoint (to round-off):
// its Jacobian is then that of its vertices, positive after orientation.
bool straight(const Mesh& mesh, int64_t t) {
  static const int kEdge[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  const int64_t* v = &mesh.tets[10 * t];
  for (int e = 0; e < 6; ++e) {
    const Eigen::Vector3d a = node_x(mesh, v[kEdge[e][0]]), b = node_x(mesh, v[kEdge[e][1]]);
    if ((node_x(mesh, v[4 + e]) - 0.5 * (a + b)).norm() > 1e-12 * (b - a).norm()) return false;
  }
  return true;
}

// The Jacobian dX/dxi of P2 tetrahedron t at reference point xi.
double p2_jacobian(const Mesh& mesh, int64_t t, const Eigen::Vector3d& xi) {
  double dN[30];
  tet_shape(2, xi, nullptr, dN);
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
  for (int a = 0; a < 10; ++a)
    J += node_x(mesh, mesh.tets[10 * t + a]) *
         Eigen::RowVector3d(dN[3 * a], dN[3 * a + 1], dN[3 * a + 2]);
  return J.determinant();
}

}  // namespace

std::string MeshLabels::node(const Mesh& mesh, int64_t n) const {
  const std::string name = node_tags.empty() ? "node " + std::to_string(n) + " (index)"
                                             : "node " + std::to_string(node_tags[n]);
  return name + " at " + point(mesh, n);
}

std::string MeshLabels::tet(const Mesh& mesh, int64_t t) const {
  std::string name = tet_tags.empty() ? "tetrahedron " + std::to_string(t) + " (index)"
                                      : "element " + std::to_string(tet_tags[t]);
  name += " (vertices";
  for (int a = 0; a < 4; ++a) name += " " + point(mesh, mesh.tets[t * mesh.nodes_per_tet() + a]);
  return name + ")";
}

void check_finite_coordinates(const Mesh& mesh, const std::string& file, const MeshLabels& labels) {
  for (int64_t n = 0; n < mesh.num_nodes(); ++n)
    for (int d = 0; d < 3; ++d)
      if (!std::isfinite(mesh.x[3 * n + d]))
        throw InputError(file + ": " + labels.node(mesh, n) +
                         ": a coordinate is not a finite number (NaN, infinite, or too large "
                         "for a double)");
}

void check_curved_tets(const Mesh& mesh, const std::string& file, const MeshLabels& labels) {
  if (mesh.order != 2) return;
  std::vector<Eigen::Vector3d> points;
  for (int a = 0; a < 10; ++a) points.push_back(tet_node(2, a));
  // A Jacobian that is not positive at a point of one of the element routines' rules stops
  // them; the nodes are checked as well.
  for (int degree : {kP2Degrees.stiffness, kP2Degrees.volume, kP2Degrees.body, kP2Degrees.mass}) {
    const auto& rule = tet_quadrature(degree).points;
    points.insert(points.end(), rule.begin(), rule.end());
  }
  for (int64_t t = 0; t < mesh.num_tets(); ++t) {
    if (straight(mesh, t)) continue;
    for (const auto& xi : points) {
      const double det = p2_jacobian(mesh, t, xi);
      if (!(det > 0)) {
        std::ostringstream s;
        s << file << ": " << labels.tet(mesh, t)
          << " is inverted or curved too strongly: its Jacobian is " << det
          << " at reference point (" << xi.transpose() << ")";
        throw InputError(s.str());
      }
    }
  }
}

void check_duplicate_nodes(const Mesh& mesh, const std::string& file, const MeshLabels& labels) {
  const int64_t n = mesh.num_nodes();
  if (n < 2) return;
  Eigen::Vector3d lo = node_x(mesh, 0), hi = lo;
  for (int64_t i = 1; i < n; ++i) {
    lo = lo.cwiseMin(node_x(mesh, i));
    hi = hi.cwiseMax(node_x(mesh, i));
  }
  // Coordinates on a grid of 1e-12 of the extent: equal cells are the same place (two nodes
  // a hair apart across a cell's border escape; exact copies, the usual case, never do).
  const double cell = 1e-12 * std::max((hi - lo).maxCoeff(), 1e-300);
  std::vector<std::array<int64_t, 3>> keys(n);
  for (int64_t i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) keys[i][d] = std::llround((mesh.x[3 * i + d] - lo[d]) / cell);
  std::vector<int64_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int64_t a, int64_t b) { return keys[a] != keys[b] ? keys[a] < keys[b] : a < b; });
  for (int64_t k = 1; k < n; ++k) {
    const int64_t a = order[k - 1], b = order[k];
    if (keys[a] == keys[b])
      throw InputError(file + ": " + labels.node(mesh, a) + " and " + labels.node(mesh, b) +
                       " are at the same place: the tetrahedra on either side are not "
                       "connected (a crack, or a volume meshed twice)");
  }
}

void check_no_overlap(const Mesh& mesh, const FaceIndex& faces, const std::string& file,
                      const MeshLabels& labels) {
  const auto& o = faces.overlap();
  if (o.first < 0) return;
  throw InputError(file + ": " + labels.tet(mesh, o.first) + " and " + labels.tet(mesh, o.second) +
                   " overlap: they share a face but lie on the same side of it (or a third "
                   "tetrahedron shares it too); one of them is inverted or folded over");
}

std::string quality_warning(const Mesh& mesh, const std::string& file, const MeshLabels& labels) {
  const int npe = mesh.nodes_per_tet();
  int64_t worst = -1, poor = 0;
  double worst_quality = kPoorTetQuality;
  for (int64_t t = 0; t < mesh.num_tets(); ++t) {
    const int64_t* v = &mesh.tets[npe * t];
    const double q =
        tet_quality(&mesh.x[3 * v[0]], &mesh.x[3 * v[1]], &mesh.x[3 * v[2]], &mesh.x[3 * v[3]]);
    if (q >= kPoorTetQuality) continue;
    ++poor;
    if (worst < 0 || q < worst_quality) worst = t, worst_quality = q;
  }
  if (poor == 0) return {};
  std::ostringstream s;
  s.precision(3);
  s << file << ": " << labels.tet(mesh, worst) << " has a mean-ratio quality of " << worst_quality
    << " (1 is regular), and " << poor << (poor == 1 ? " tetrahedron is" : " tetrahedra are")
    << " below " << kPoorTetQuality
    << " (a sliver 1/650 as thick as it is wide has 0.02): its stiffness is ill-conditioned "
       "and its strains and stresses unreliable; remesh with optimisation (gmsh: "
       "Mesh.Optimize, Mesh.OptimizeNetgen) unless the numbers near it do not matter";
  return s.str();
}

std::string units_warning(const Mesh& mesh, const std::string& file) {
  if (mesh.num_nodes() == 0) return {};
  Eigen::Vector3d lo = node_x(mesh, 0), hi = lo;
  for (int64_t i = 1; i < mesh.num_nodes(); ++i) {
    lo = lo.cwiseMin(node_x(mesh, i));
    hi = hi.cwiseMax(node_x(mesh, i));
  }
  const double extent = (hi - lo).maxCoeff();
  if (extent <= 100 && extent >= 1e-4) return {};
  std::ostringstream s;
  s << file << ": the mesh spans " << extent << " m (bounding box [" << lo[0] << ", " << hi[0]
    << "] x [" << lo[1] << ", " << hi[1] << "] x [" << lo[2] << ", " << hi[2] << "]); "
    << (extent > 100 ? "is it drawn in millimetres? " : "is it drawn in other units? ")
    << "A deck's numbers are SI (metres)";
  return s.str();
}

}  // namespace hs
