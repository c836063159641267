#include "solvers/effectors.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "common/error.hpp"
#include "fem/shape.hpp"

namespace hs {

bool locate(const Mesh& mesh, const std::array<double, 3>& X, std::vector<int64_t>& nodes,
            std::vector<double>& N) {
  const int npe = mesh.nodes_per_tet();
  double best = -1e300;
  int64_t best_tet = -1;
  Eigen::Vector3d best_xi;
  for (int64_t t = 0; t < mesh.num_tets(); ++t) {
    const int64_t* tet = &mesh.tets[t * npe];
    Eigen::Matrix3d A;
    Eigen::Vector3d x0(mesh.x[3 * tet[0]], mesh.x[3 * tet[0] + 1], mesh.x[3 * tet[0] + 2]);
    for (int k = 1; k <= 3; ++k)
      for (int d = 0; d < 3; ++d) A(d, k - 1) = mesh.x[3 * tet[k] + d] - x0(d);
    const Eigen::Vector3d xi = A.partialPivLu().solve(Eigen::Vector3d(X[0], X[1], X[2]) - x0);
    const double smallest = std::min({1 - xi.sum(), xi(0), xi(1), xi(2)});
    if (smallest > best) {  // the most inside tetrahedron (robust on shared faces and edges)
      best = smallest;
      best_tet = t;
      best_xi = xi;
    }
  }
  if (best_tet < 0 || best < -1e-9) return false;
  nodes.assign(&mesh.tets[best_tet * npe], &mesh.tets[best_tet * npe] + npe);
  N.resize(npe);
  tet_shape(mesh.order, best_xi, N.data(), nullptr);
  return true;
}

Effectors::Effectors(const Config& config, Problem& problem) {
  const Mesh& mesh = problem.mesh();
  if (!config.control) return;
  for (const auto& e : config.control->effectors) {
    std::vector<int64_t> nodes;
    std::vector<double> N;
    const std::string where = config.deck_path + ": control.effectors '" + e.name + "'";
    if (!e.point.empty()) {
      auto it = mesh.node_groups.find(e.point);
      if (it == mesh.node_groups.end() || it->second.size() != 1)
        throw InputError(where + ": point group '" + e.point + "' must hold exactly one node (" +
                         (it == mesh.node_groups.end()
                              ? std::string("not in the mesh")
                              : std::to_string(it->second.size()) + " nodes") +
                         ")");
      nodes = {it->second[0]};
      N = {1.0};
    } else if (!locate(mesh, e.position, nodes, N)) {
      throw InputError(where + ": position (" + std::to_string(e.position[0]) + ", " +
                       std::to_string(e.position[1]) + ", " + std::to_string(e.position[2]) +
                       ") lies outside the mesh");
    }
    names_.push_back(e.name);
    configs_.push_back(e);
    for (int d = 0; d < 3; ++d) {
      double X = 0;
      for (size_t a = 0; a < nodes.size(); ++a) X += N[a] * mesh.x[3 * nodes[a] + d];
      reference_.push_back(X);
    }
    append_point_rows(problem, nodes, N, rows_);
  }
}

void append_point_rows(Problem& problem, const std::vector<int64_t>& nodes,
                       const std::vector<double>& N, std::vector<Vec>& rows) {
  const Distribution& dist = problem.distribution();
  for (int d = 0; d < 3; ++d) {
    Vec row = problem.create_vector();
    if (dist.rank == 0)
      for (size_t a = 0; a < nodes.size(); ++a)
        HS_PETSC(VecSetValue(row, static_cast<PetscInt>(3 * dist.new_of_old[nodes[a]] + d), N[a],
                             ADD_VALUES));
    HS_PETSC(VecAssemblyBegin(row));
    HS_PETSC(VecAssemblyEnd(row));
    rows.push_back(row);
  }
}

Effectors::~Effectors() {
  for (auto& v : rows_) VecDestroy(&v);
}

int Effectors::index(const std::string& name) const {
  for (size_t e = 0; e < names_.size(); ++e)
    if (names_[e] == name) return static_cast<int>(e);
  return -1;
}

std::vector<double> Effectors::positions(Vec u) const {
  std::vector<double> x(reference_);
  for (size_t r = 0; r < rows_.size(); ++r) {
    PetscScalar dot = 0;
    HS_PETSC(VecDot(rows_[r], u, &dot));
    x[r] += dot;
  }
  return x;
}

}  // namespace hs
