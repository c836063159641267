#include "solvers/constraints/cable_path.hpp"

#include <cmath>

#include "common/error.hpp"
#include "solvers/effectors.hpp"
#include "solvers/petsc_check.hpp"

namespace hs {

CablePath::CablePath(const CableConfig& config, Problem& problem, const std::string& deck_path)
    : config_(config) {
  for (size_t i = 0; i < config.points.size(); ++i) {
    const auto& X = config.points[i];
    MaterialPoint p;
    if (!locate(problem, X, p))
      throw InputError(deck_path + ": cables '" + config.name + "' points[" + std::to_string(i) +
                       "] (" + std::to_string(X[0]) + ", " + std::to_string(X[1]) + ", " +
                       std::to_string(X[2]) + ") lies outside the mesh");
    std::vector<PetscInt> dofs;
    for (size_t a = 0; a < p.nodes.size(); ++a)
      for (int d = 0; d < 3; ++d)
        dofs.push_back(p.free_dofs[3 * a + d] ? static_cast<PetscInt>(3 * p.nodes[a] + d) : -1);
    dofs_.push_back(dofs);
    shape_.push_back(p.N);
    for (int d = 0; d < 3; ++d) reference_.push_back(X[d]);
    append_point_rows(problem, p.nodes, p.N, rows_);
  }
  // The turning stiffness couples the points of each segment (the last one ends at the
  // fixed pull point, if any): one block of the tangent each, set by rank 0.
  int rank = 0;
  MPI_Comm_rank(problem.comm(), &rank);
  const size_t segments = dofs_.size() - 1 + (config_.pull_point ? 1 : 0);
  for (size_t i = 0; rank == 0 && i < segments; ++i) {
    std::vector<PetscInt> ends(dofs_[i]);
    if (i + 1 < dofs_.size()) ends.insert(ends.end(), dofs_[i + 1].begin(), dofs_[i + 1].end());
    couplings_.push_back(problem.add_coupling(std::move(ends)));
  }
}

std::vector<double> CablePath::positions(Vec u) const {
  std::vector<PetscScalar> dots(rows_.size());
  HS_PETSC(VecMDot(u, static_cast<PetscInt>(rows_.size()), rows_.data(), dots.data()));
  std::vector<double> x(reference_);
  for (size_t r = 0; r < rows_.size(); ++r) x[r] += dots[r];
  return x;
}

// The polyline the cable follows: the material points, then the pull point (fixed).
std::vector<std::array<double, 3>> CablePath::path(const std::vector<double>& x) const {
  std::vector<std::array<double, 3>> p;
  for (size_t i = 0; i < x.size(); i += 3) p.push_back({x[i], x[i + 1], x[i + 2]});
  if (config_.pull_point) p.push_back(*config_.pull_point);
  return p;
}

double CablePath::length(Vec u) const {
  const auto p = path(positions(u));
  double L = 0;
  for (size_t i = 0; i + 1 < p.size(); ++i)
    L += std::hypot(p[i + 1][0] - p[i][0], p[i + 1][1] - p[i][1], p[i + 1][2] - p[i][2]);
  return L;
}

void CablePath::pull_direction(Vec u, Vec g) const {
  const auto p = path(positions(u));
  const size_t points = rows_.size() / 3;  // path entries past these are the pull point
  // -dL/dx_k: the unit vectors from x_k towards its neighbours on the path.
  std::vector<PetscScalar> coeff(rows_.size(), 0.0);
  for (size_t i = 0; i + 1 < p.size(); ++i) {
    const double len =
        std::hypot(p[i + 1][0] - p[i][0], p[i + 1][1] - p[i][1], p[i + 1][2] - p[i][2]);
    for (int d = 0; d < 3; ++d) {
      const double e = (p[i + 1][d] - p[i][d]) / len;
      coeff[3 * i + d] += e;                            // x_i towards x_{i+1}
      if (i + 1 < points) coeff[3 * (i + 1) + d] -= e;  // x_{i+1} towards x_i
    }
  }
  distribute(coeff, g);
}

void CablePath::distribute(const std::vector<double>& f, Vec g) const {
  HS_PETSC(VecSet(g, 0.0));
  HS_PETSC(
      VecMAXPY(g, static_cast<PetscInt>(rows_.size()), f.data(), const_cast<Vec*>(rows_.data())));
}

void CablePath::set_stiffness(Vec u, double T, Problem& problem) const {
  const auto p = path(positions(u));
  if (couplings_.empty()) return;  // ranks other than 0
  const size_t points = dofs_.size();
  for (size_t i = 0; i + 1 < p.size(); ++i) {
    std::array<double, 3> e;
    const double len =
        std::hypot(p[i + 1][0] - p[i][0], p[i + 1][1] - p[i][1], p[i + 1][2] - p[i][2]);
    for (int d = 0; d < 3; ++d) e[d] = (p[i + 1][d] - p[i][d]) / len;
    double P[3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) P[a][b] = T * ((a == b) - e[a] * e[b]) / len;
    // The segment's two ends (the pull point is fixed: only x_i then), with signs +1, -1.
    std::vector<double> w;  // N_a times the end's sign, per dof
    for (size_t end = i; end <= i + 1 && end < points; ++end)
      for (size_t a = 0; a < shape_[end].size(); ++a)
        for (int d = 0; d < 3; ++d) w.push_back((end == i ? 1.0 : -1.0) * shape_[end][a]);
    const size_t n = w.size();
    std::vector<PetscScalar> block(n * n);
    for (size_t r = 0; r < n; ++r)
      for (size_t c = 0; c < n; ++c) block[r * n + c] = w[r] * w[c] * P[r % 3][c % 3];
    problem.set_coupling(couplings_[i], block);
  }
}

}  // namespace hs
