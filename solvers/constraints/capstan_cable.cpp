#include "solvers/constraints/capstan_cable.hpp"

#include "actuators/capstan.hpp"
#include "solvers/problem.hpp"

namespace hs {

CapstanCable::CapstanCable(const CableConfig& config, ConstraintContext& context)
    : Cable(config, context), friction_(config.friction) {
  int rank = 0;
  MPI_Comm_rank(problem_.comm(), &rank);
  if (rank != 0) return;
  std::vector<PetscInt> dofs;
  for (size_t i = 0; i < path_.points(); ++i)
    dofs.insert(dofs.end(), path_.dofs(i).begin(), path_.dofs(i).end());
  coupling_ = problem_.add_coupling(dofs);
}

std::vector<double> CapstanCable::point_forces(Vec u) const {
  const CapstanForces f = capstan_forces(path_.path(u), friction_, false);
  std::vector<double> out(3 * path_.points());
  for (size_t i = 0; i < path_.points(); ++i)
    for (int a = 0; a < 3; ++a) out[3 * i + a] = f.force[i][a];
  return out;
}

void CapstanCable::forces(Vec u, Vec g) const {
  path_.distribute(point_forces(u), g);
  problem_.zero_constrained(g);
}

void CapstanCable::add_load(Vec u, double /*s*/, Vec load) {
  path_.distribute(point_forces(u), pull_);
  HS_PETSC(VecAXPY(load, multiplier(), pull_));
}

// The tangent of R = ... - T F(x(u)): -T N_ia dF_i/dx_m N_mb for node a of point i and node b
// of point m (the pull point is fixed: its rows and columns drop out).
void CapstanCable::set_stiffness(Vec u, Problem& problem) {
  const auto path = path_.path(u);
  if (coupling_ < 0) return;  // ranks other than 0
  const CapstanForces f = capstan_forces(path, friction_, true);
  const size_t dim = 3 * path.size();
  std::vector<size_t> first;  // each point's first row in the block
  size_t n = 0;
  for (size_t i = 0; i < path_.points(); ++i) {
    first.push_back(n);
    n += path_.dofs(i).size();
  }
  std::vector<PetscScalar> block(n * n, 0.0);
  for (size_t i = 0; i < path_.points(); ++i)
    for (size_t m = 0; m < path_.points(); ++m) {
      const auto &Ni = path_.shape(i), &Nm = path_.shape(m);
      for (size_t a = 0; a < Ni.size(); ++a)
        for (size_t b = 0; b < Nm.size(); ++b)
          for (int x = 0; x < 3; ++x)
            for (int y = 0; y < 3; ++y)
              block[(first[i] + 3 * a + x) * n + first[m] + 3 * b + y] =
                  -multiplier() * Ni[a] * Nm[b] * f.jacobian[(3 * i + x) * dim + 3 * m + y];
    }
  problem.set_coupling(coupling_, block);
}

nlohmann::json CapstanCable::report() const {
  nlohmann::json j = Cable::report();
  j["friction"] = friction_;
  return j;
}

}  // namespace hs
