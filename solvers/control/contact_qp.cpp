#include "solvers/control/contact_qp.hpp"

#include <mpi.h>

#include <cmath>

#include "common/error.hpp"
#include "solvers/petsc_check.hpp"

namespace hs {
namespace {

// A node reaches a candidate when its gap is within this many barrier distances (5 % of the
// mesh's bounding diagonal with the default distance): farther than a control step moves a
// node on the decks, and every candidate costs one more solve a step.
constexpr double kReachInDistances = 50;
// A gap within this fraction of the barrier distance is closed.
constexpr double kClosedInDistances = 1e-3;

ObstacleContact& contact_of(Problem& problem) {
  if (!problem.contact())
    throw InputError("control.contact_forces: qp needs obstacles and contact.surfaces");
  return *problem.contact();
}

}  // namespace

ContactQp::ContactQp(Problem& problem, Effectors& effectors)
    : problem_(problem),
      effectors_(effectors),
      contact_(contact_of(problem)),
      reach_(kReachInDistances * contact_.barrier().distance),
      gap_tolerance_(kClosedInDistances * contact_.barrier().distance),
      work_(problem.create_vector()) {}

void ContactQp::begin_step(Vec u) {
  if (contact_.holds_forces()) return;
  const Problem::LocalView view(u, work_);
  contact_.hold_forces(view.values(), 1.0);
}

ContactBlocks ContactQp::linearize(Vec u, KSP ksp, BorderedSystem& system,
                                   const ConstraintLinearization& lin,
                                   const std::vector<bool>& held,
                                   const std::vector<Vec>& actuator_responses,
                                   const std::vector<int>& actuator_constraints,
                                   const std::vector<ControlTarget>& targets,
                                   const Eigen::MatrixXd& W_a, const Eigen::VectorXd& delta) {
  const MPI_Comm comm = problem_.comm();
  const int E = effectors_.size(), n = static_cast<int>(actuator_responses.size());
  const auto& nodes = contact_.nodes();
  {
    const Problem::LocalView view(u, work_);
    own_ = contact_.candidates(view.values(), 1.0, reach_);
  }
  // Each candidate as [obstacle, gap, normal, held force, a force effector counts it (E)].
  const int width = 6 + E;
  std::vector<double> mine;
  for (const auto& c : own_) {
    const int32_t node = nodes[c.index];
    mine.insert(mine.end(), {double(c.obstacle), c.gap, c.normal(0), c.normal(1), c.normal(2),
                             contact_.held()[c.index].force});
    for (int e = 0; e < E; ++e) {
      const std::vector<char>* only = effectors_.contact_nodes(e);
      mine.push_back(effectors_.obstacle(e) == c.obstacle && (!only || (*only)[node]));
    }
  }
  int size = 0, rank = 0;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  const int count = static_cast<int>(mine.size());
  std::vector<int> counts(size), displs(size, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
  std::vector<double> all(displs[size - 1] + counts[size - 1]);
  MPI_Allgatherv(mine.data(), count, MPI_DOUBLE, all.data(), counts.data(), displs.data(),
                 MPI_DOUBLE, comm);
  const int N = static_cast<int>(all.size()) / width;
  offset_ = displs[rank] / width;
  obstacle_.resize(N);
  normal_.resize(N);
  ContactBlocks k;
  k.gap.resize(N);
  k.held.resize(N);
  for (int j = 0; j < N; ++j) {
    const double* c = &all[j * width];
    obstacle_[j] = static_cast<int>(c[0]);
    k.gap(j) = c[1];
    normal_[j] = Eigen::Vector3d(c[2], c[3], c[4]);
    k.held(j) = c[5];
  }

  // The responses to unit normal forces (zero on the Dirichlet dofs: no force acts there).
  std::vector<Vec> f(N), du(N);
  while (static_cast<int>(response_.size()) < N) {
    response_.push_back(problem_.create_vector());
    load_.push_back(problem_.create_vector());
  }
  for (int j = 0; j < N; ++j) {
    f[j] = load_[j];
    du[j] = response_[j];
    HS_PETSC(VecSet(f[j], 0.0));
    if (j < offset_ || j >= offset_ + static_cast<int>(own_.size())) continue;
    PetscScalar* a;
    HS_PETSC(VecGetArray(f[j], &a));
    const int32_t node = nodes[own_[j - offset_].index];
    for (int d = 0; d < 3; ++d) a[3 * node + d] = normal_[j](d);
    HS_PETSC(VecRestoreArray(f[j], &a));
  }
  for (Vec v : f) problem_.zero_constrained(v);
  if (N && !system.load_responses(ksp, f, lin, held, du, zeta_))
    throw SolveError("control step: the responses to the contact forces failed");

  // The normal moves of the own candidates, summed over the ranks.
  k.G_cc = Eigen::MatrixXd::Zero(N, N);
  k.G_ca = Eigen::MatrixXd::Zero(N, n);
  auto normal_moves = [&](Vec v, auto&& put) {
    const PetscScalar* a;
    HS_PETSC(VecGetArrayRead(v, &a));
    for (size_t i = 0; i < own_.size(); ++i) {
      const int32_t node = nodes[own_[i].index];
      const int j = offset_ + static_cast<int>(i);
      put(j, normal_[j].dot(Eigen::Vector3d(a[3 * node], a[3 * node + 1], a[3 * node + 2])));
    }
    HS_PETSC(VecRestoreArrayRead(v, &a));
  };
  for (int j = 0; j < N; ++j) normal_moves(du[j], [&](int i, double v) { k.G_cc(i, j) = v; });
  for (int a = 0; a < n; ++a)
    normal_moves(actuator_responses[a], [&](int i, double v) { k.G_ca(i, a) = v; });
  MPI_Allreduce(MPI_IN_PLACE, k.G_cc.data(), N * N, MPI_DOUBLE, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, k.G_ca.data(), N * n, MPI_DOUBLE, MPI_SUM, comm);
  k.G_cc = 0.5 * (k.G_cc + k.G_cc.transpose()).eval();  // symmetric up to the solves' round-off

  k.growth_a = Eigen::MatrixXd::Zero(n, n);  // the controller's own growth goes in there
  k.growth_c.resize(n, N);
  std::vector<PetscScalar> dots(N);
  for (int a = 0; a < n; ++a) {
    if (N) HS_PETSC(VecMDot(lin.g[actuator_constraints[a]], N, du.data(), dots.data()));
    for (int j = 0; j < N; ++j) k.growth_c(a, j) = dots[j];
  }

  // The effectors: a position's rows through the responses, a force's through the forces of
  // its own candidates (minus their normals: the body's force on the obstacle).
  const int r = static_cast<int>(W_a.rows());
  k.W_a = W_a;
  k.delta = delta;
  k.W_c = Eigen::MatrixXd::Zero(r, N);
  k.approach.assign(r, -1);
  k.approach_factor = Eigen::VectorXd::Zero(r);
  int row = 0;
  for (const auto& t : targets) {
    const int e = effectors_.index(t.effector);
    const auto& ec = effectors_.config(e);
    double asked = 0;
    for (int d = 0; d < 3; ++d)
      if (ec.directions[d]) asked += t.position[d] * t.position[d];
    asked = std::sqrt(asked);
    int nearest = -1;
    for (int j = 0; j < N; ++j)
      if (all[j * width + 6 + e] != 0 && (nearest < 0 || k.gap(j) < k.gap(nearest))) nearest = j;
    for (int d = 0; d < 3; ++d) {
      if (!ec.directions[d]) continue;
      const int at = row++;
      if (!effectors_.is_force(e)) {
        if (N) HS_PETSC(VecMDot(effectors_.row(e, d), N, du.data(), dots.data()));
        for (int j = 0; j < N; ++j) k.W_c(at, j) = ec.weight * dots[j];
        continue;
      }
      for (int j = 0; j < N; ++j)
        if (all[j * width + 6 + e] != 0) k.W_c(at, j) = -ec.weight * normal_[j](d);
      if (nearest >= 0 && k.gap(nearest) > gap_tolerance_) {
        k.approach[at] = nearest;
        k.approach_factor(at) = ec.weight * normal_[nearest](d) * asked / k.gap(nearest);
      }
    }
  }
  k.gap_tolerance = gap_tolerance_;
  return k;
}

Eigen::VectorXd ContactQp::apply(Vec u, const Eigen::VectorXd& dforce) {
  const int N = num_candidates();
  if (N == 0) return Eigen::VectorXd::Zero(zeta_.rows());
  HS_PETSC(VecMAXPY(u, N, dforce.data(), response_.data()));
  auto& held = contact_.held();
  for (size_t i = 0; i < own_.size(); ++i) {
    const int j = offset_ + static_cast<int>(i);
    ObstacleContact::Held& h = held[own_[i].index];
    h.force = std::max(0.0, h.force + dforce(j));
    h.obstacle = obstacle_[j];
    h.normal = normal_[j];
  }
  // The forces turned to the obstacles' normals where the correction put their nodes: then
  // the answer's equilibrium (and the next step's free configuration) hold the same loads.
  const Problem::LocalView view(u, work_);
  contact_.turn_held_normals(view.values(), 1.0);
  return zeta_ * dforce;
}

}  // namespace hs
