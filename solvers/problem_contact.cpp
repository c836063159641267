// Problem's contact: the obstacles' and the surfaces' forces, their rows for the controller's
// force effectors, the steps' limits and the friction's lag (docs/contact.md).
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "solvers/problem.hpp"

namespace hs {

void Problem::accept_state(Vec u, double s) {
  if (!friction_lag_held_) take_friction_lag(u, s);
}

void Problem::take_friction_lag(Vec u, double s) {
  const bool obstacles = contact_ && contact_->has_friction();
  const bool surfaces = self_contact_ && self_contact_->has_friction();
  if (!obstacles && !surfaces) return;
  LocalView view(u, u_work_);
  if (obstacles) contact_->accept(view.values(), s);
  if (surfaces) self_contact_->accept(view.values());
}

std::string Problem::refusal() const {
  if (self_touch_) return "a node reached a triangle of the contact surfaces (contact.self)";
  if (obstacle_reached_ >= 0)
    return "a node reached obstacle '" + contact_->obstacles()[obstacle_reached_].name + "'";
  return "inverted element";
}

ObstacleContact::Totals Problem::contact_totals(Vec u, double s) const {
  if (!contact_) return {};
  VecHandle uw;
  HS_PETSC(VecDuplicate(u_work_, uw.out()));
  LocalView view(u, uw);
  return contact_->totals(view.values(), s);
}

std::array<double, 3> Problem::contact_force(Vec u, double s, int o,
                                             const std::vector<char>* only) const {
  std::array<double, 3> f{0, 0, 0};
  if (contact_) {
    VecHandle uw;
    HS_PETSC(VecDuplicate(u_work_, uw.out()));
    LocalView view(u, uw);
    const Eigen::Vector3d here = contact_->force_on(view.values(), s, o, only);
    for (int d = 0; d < 3; ++d) f[d] = here(d);
  }
  MPI_Allreduce(MPI_IN_PLACE, f.data(), 3, MPI_DOUBLE, MPI_SUM, comm_);
  return f;
}

double Problem::contact_force_rows(Vec u, double s, int o, const std::vector<char>* only,
                                   Vec rows[3]) const {
  VecHandle uw;
  HS_PETSC(VecDuplicate(u_work_, uw.out()));
  LocalView view(u, uw);
  double* r[3];
  for (int d = 0; d < 3; ++d) {
    HS_PETSC(VecSet(rows[d], 0.0));
    HS_PETSC(VecGetArray(rows[d], &r[d]));
  }
  double touching = 0;  // the largest row entry: zero when no node is within reach
  if (contact_) {
    contact_->force_rows(view.values(), s, o, only, r);
    for (int d = 0; d < 3; ++d)
      for (int64_t k = 0; k < 3 * dist_.num_owned(); ++k)
        touching = std::max(touching, std::abs(r[d][k]));
  }
  MPI_Allreduce(MPI_IN_PLACE, &touching, 1, MPI_DOUBLE, MPI_MAX, comm_);
  double gap = 0;
  if (contact_ && touching == 0) {
    const ObstacleContact::Nearest near = contact_->nearest(view.values(), s, o, only);
    struct {
      double gap;
      int rank;
    } best{near.node >= 0 ? near.gap : std::numeric_limits<double>::max(), dist_.rank};
    MPI_Allreduce(MPI_IN_PLACE, &best, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm_);
    gap = best.gap;
    if (best.rank == dist_.rank && near.node >= 0)
      for (int d = 0; d < 3; ++d)
        for (int j = 0; j < 3; ++j) r[d][3 * near.node + j] = near.normal(d) * near.normal(j);
  }
  for (int d = 0; d < 3; ++d) {
    HS_PETSC(VecRestoreArray(rows[d], &r[d]));
    zero_constrained(rows[d]);
  }
  return gap;
}

std::array<double, 3> Problem::self_contact_force(Vec u, int a, int b) const {
  if (!self_contact_) return {0, 0, 0};
  const PetscScalar* ua;
  HS_PETSC(VecGetArrayRead(u, &ua));
  const std::array<double, 3> f = self_contact_->force_between(ua, a, b);
  HS_PETSC(VecRestoreArrayRead(u, &ua));
  return f;
}

double Problem::self_contact_force_rows(Vec u, int a, int b, Vec rows[3]) const {
  double* r[3];
  for (int d = 0; d < 3; ++d) {
    HS_PETSC(VecSet(rows[d], 0.0));
    HS_PETSC(VecGetArray(rows[d], &r[d]));
  }
  double gap = 0;
  if (self_contact_) {
    const PetscScalar* ua;
    HS_PETSC(VecGetArrayRead(u, &ua));
    gap = self_contact_->force_rows_between(ua, a, b, r);
    HS_PETSC(VecRestoreArrayRead(u, &ua));
  }
  for (int d = 0; d < 3; ++d) {
    HS_PETSC(VecRestoreArray(rows[d], &r[d]));
    zero_constrained(rows[d]);
  }
  return gap;
}

double Problem::contact_step_limit(Vec u, Vec du, double s) const {
  return std::min(self_contact_step_limit(u, du), obstacle_step_limit(u, du, s));
}

double Problem::obstacle_step_limit(Vec u, Vec du, double s) const {
  if (!contact_) return 1;
  const AddSeconds timed(timers_.contact_s);
  const PetscScalar *ua, *da;
  HS_PETSC(VecGetArrayRead(u, &ua));
  HS_PETSC(VecGetArrayRead(du, &da));
  double alpha = contact_->step_limit(ua, da, s);
  HS_PETSC(VecRestoreArrayRead(du, &da));
  HS_PETSC(VecRestoreArrayRead(u, &ua));
  MPI_Allreduce(MPI_IN_PLACE, &alpha, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return alpha;
}

double Problem::self_contact_step_limit(Vec u, Vec du) const {
  if (!self_contact_) return 1;
  const AddSeconds timed(timers_.contact_s);
  const PetscScalar *ua, *da;
  HS_PETSC(VecGetArrayRead(u, &ua));
  HS_PETSC(VecGetArrayRead(du, &da));
  const double alpha = self_contact_->step_limit(ua, da);
  HS_PETSC(VecRestoreArrayRead(du, &da));
  HS_PETSC(VecRestoreArrayRead(u, &ua));
  return alpha;
}

void Problem::keep_outside_contact(Vec from, Vec u, double s) const {
  if (!has_contact()) return;
  VecHandle step;
  HS_PETSC(VecDuplicate(u, step.out()));
  HS_PETSC(VecWAXPY(step, -1.0, from, u));
  if (self_contact_ && self_contact_step_limit(from, step) < 1) {
    HS_PETSC(VecCopy(from, u));
    dofs_.apply(u, s);
    return;
  }
  const double alpha = obstacle_step_limit(from, step, s);
  if (alpha == 1) return;
  HS_PETSC(VecWAXPY(u, alpha, step, from));
  dofs_.apply(u, s);
}

SelfContact::Totals Problem::self_contact_totals(Vec u) const {
  if (!self_contact_) return {};
  const PetscScalar* ua;
  HS_PETSC(VecGetArrayRead(u, &ua));
  const SelfContact::Totals t = self_contact_->totals(ua);
  HS_PETSC(VecRestoreArrayRead(u, &ua));
  return t;
}

SelfContact::NodeValues Problem::self_contact_node_values(Vec u) const {
  if (!self_contact_) return {};
  const PetscScalar* ua;
  HS_PETSC(VecGetArrayRead(u, &ua));
  SelfContact::NodeValues v = self_contact_->node_values(ua, dist_.num_owned());
  HS_PETSC(VecRestoreArrayRead(u, &ua));
  face_means(v.pressure, 1);
  if (!v.friction.empty()) face_means(v.friction, 3);
  return v;
}

ObstacleContact::NodeValues Problem::contact_node_values(Vec u, double s) const {
  if (!contact_) return {};
  VecHandle uw;
  HS_PETSC(VecDuplicate(u_work_, uw.out()));
  ObstacleContact::NodeValues v;
  {
    LocalView view(u, uw);
    v = contact_->node_values(view.values(), s, dist_.num_owned());
  }
  face_means(v.pressure, 1);
  face_means(v.friction, 3);
  return v;
}

void Problem::face_means(std::vector<double>& values, int width) const {
  const int npf = dist_.nodes_per_face();
  if (npf != 6) return;
  const int64_t owned = dist_.num_owned();
  // Three ghosted vectors of 3 per node: the values, the faces' means at the nodes, the
  // nodes' shares of the faces' areas (the first entry of each node).
  VecHandle in, mean, share;
  HS_PETSC(VecDuplicate(u_work_, in.out()));
  HS_PETSC(VecDuplicate(u_work_, mean.out()));
  HS_PETSC(VecDuplicate(u_work_, share.out()));
  HS_PETSC(VecSet(in, 0.0));
  HS_PETSC(VecSet(mean, 0.0));
  HS_PETSC(VecSet(share, 0.0));
  {
    PetscScalar* a;
    HS_PETSC(VecGetArray(in, &a));
    for (int64_t n = 0; n < owned; ++n)
      for (int c = 0; c < width; ++c) a[3 * n + c] = values[width * n + c];
    HS_PETSC(VecRestoreArray(in, &a));
  }
  HS_PETSC(VecGhostUpdateBegin(in, INSERT_VALUES, SCATTER_FORWARD));
  HS_PETSC(VecGhostUpdateEnd(in, INSERT_VALUES, SCATTER_FORWARD));
  Vec in_local, mean_local, share_local;
  HS_PETSC(VecGhostGetLocalForm(in, &in_local));
  HS_PETSC(VecGhostGetLocalForm(mean, &mean_local));
  HS_PETSC(VecGhostGetLocalForm(share, &share_local));
  const PetscScalar* v;
  PetscScalar *m, *a;
  HS_PETSC(VecGetArrayRead(in_local, &v));
  HS_PETSC(VecGetArray(mean_local, &m));
  HS_PETSC(VecGetArray(share_local, &a));
  std::set<std::array<int32_t, 3>> seen;  // a face in two of the groups counts once
  for (const auto& group : contact_surfaces_) {
    const auto it = dist_.faces.find(group);
    if (it == dist_.faces.end()) continue;
    for (size_t f = 0; f < it->second.size() / npf; ++f) {
      const int32_t* nodes = &it->second[f * npf];
      std::array<int32_t, 3> key = {nodes[0], nodes[1], nodes[2]};
      std::sort(key.begin(), key.end());
      if (!seen.insert(key).second) continue;
      const Eigen::Map<const Eigen::Vector3d> x0(&X_[3 * nodes[0]]), x1(&X_[3 * nodes[1]]),
          x2(&X_[3 * nodes[2]]);
      const double part = 0.5 * (x1 - x0).cross(x2 - x0).norm() / npf;
      double face[3] = {0, 0, 0};  // the nodes' values weighted by their equal shares
      for (int k = 0; k < npf; ++k)
        for (int c = 0; c < width; ++c) face[c] += v[3 * nodes[k] + c] / npf;
      for (int k = 0; k < npf; ++k) {
        a[3 * nodes[k]] += part;
        for (int c = 0; c < width; ++c) m[3 * nodes[k] + c] += part * face[c];
      }
    }
  }
  HS_PETSC(VecRestoreArrayRead(in_local, &v));
  HS_PETSC(VecRestoreArray(mean_local, &m));
  HS_PETSC(VecRestoreArray(share_local, &a));
  HS_PETSC(VecGhostRestoreLocalForm(in, &in_local));
  HS_PETSC(VecGhostRestoreLocalForm(mean, &mean_local));
  HS_PETSC(VecGhostRestoreLocalForm(share, &share_local));
  for (Vec w : {mean.get(), share.get()}) {
    HS_PETSC(VecGhostUpdateBegin(w, ADD_VALUES, SCATTER_REVERSE));
    HS_PETSC(VecGhostUpdateEnd(w, ADD_VALUES, SCATTER_REVERSE));
  }
  const PetscScalar *mo, *ao;
  HS_PETSC(VecGetArrayRead(mean, &mo));
  HS_PETSC(VecGetArrayRead(share, &ao));
  for (int64_t n = 0; n < owned; ++n)
    if (ao[3 * n] > 0)
      for (int c = 0; c < width; ++c) values[width * n + c] = mo[3 * n + c] / ao[3 * n];
  HS_PETSC(VecRestoreArrayRead(mean, &mo));
  HS_PETSC(VecRestoreArrayRead(share, &ao));
}

}  // namespace hs
