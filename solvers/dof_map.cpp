#include "solvers/dof_map.hpp"

#include <algorithm>
#include <stdexcept>

#include "common/error.hpp"
#include "solvers/petsc_check.hpp"

namespace hs {

DofMap::DofMap(const Config& config, const Distribution& dist, ExactDirichlet exact)
    : num_owned_(dist.num_owned()), X_(dist.x), exact_(std::move(exact)) {
  const int64_t nlocal = dist.num_local();
  global_.resize(3 * nlocal);
  for (int64_t i = 0; i < nlocal; ++i)
    for (int d = 0; d < 3; ++d)
      global_[3 * i + d] = static_cast<PetscInt>(3 * dist.local_nodes[i] + d);
  for (int64_t i = dist.num_owned(); i < nlocal; ++i)
    ghost_blocks_.push_back(static_cast<PetscInt>(dist.local_nodes[i]));

  // Dirichlet data per local dof. Entries that share a dof agree on it (the run refused
  // those that do not: check_boundary_conflicts), so which of them is kept does not matter.
  constrained_.assign(3 * nlocal, 0);
  prescribed_.assign(3 * nlocal, 0.0);
  scaled_.assign(3 * nlocal, 1);
  from_exact_.assign(3 * nlocal, 0);
  group_of_.assign(3 * nlocal, -1);
  moved_by_.assign(3 * nlocal, -1);
  for (const auto& bc : config.dirichlet) {
    if (bc.exact && !exact_)
      throw InputError(config.deck_path + ": boundary: group '" + bc.group +
                       "' asks for exact values but the deck has no exact solution");
    // Every rank lists every group, also those without a node on it.
    const auto listed = std::find(groups_.begin(), groups_.end(), bc.group);
    const int group = static_cast<int>(listed - groups_.begin());
    if (listed == groups_.end()) groups_.push_back(bc.group);
    auto it = dist.node_groups.find(bc.group);
    if (it == dist.node_groups.end()) continue;  // group has no node on this rank
    for (int32_t n : it->second)
      for (int d = 0; d < 3; ++d)
        if (bc.components[d]) {
          if (group_of_[3 * n + d] < 0) group_of_[3 * n + d] = group;
          moved_by_[3 * n + d] = group;
          constrained_[3 * n + d] = 1;
          prescribed_[3 * n + d] = bc.value[d];
          scaled_[3 * n + d] = bc.scaled;
          from_exact_[3 * n + d] = bc.exact;
        }
  }
}

Vec DofMap::create_vector(MPI_Comm comm) const {
  Vec v;
  HS_PETSC(VecCreateGhostBlock(comm, 3, 3 * static_cast<PetscInt>(num_owned_), PETSC_DECIDE,
                               static_cast<PetscInt>(ghost_blocks_.size()), ghost_blocks_.data(),
                               &v));
  HS_PETSC(VecSet(v, 0.0));
  return v;
}

void DofMap::indices(const int32_t* nodes, int n, PetscInt* idx) const {
  for (int a = 0; a < n; ++a)
    for (int d = 0; d < 3; ++d) {
      const auto l = 3 * static_cast<int64_t>(nodes[a]) + d;
      idx[3 * a + d] = constrained_[l] ? -1 : global_[l];
    }
}

double DofMap::prescribed_value(int64_t l, double s) const {
  if (from_exact_[l]) {
    const int64_t node = l / 3;
    const std::array<double, 3> X = {X_[3 * node], X_[3 * node + 1], X_[3 * node + 2]};
    return exact_(X, s)[l % 3];
  }
  const double move = moves_.empty() ? 0.0 : moves_[moved_by_[l]][l % 3];
  return prescribed_[l] * (scaled_[l] ? s : 1.0) + move;
}

void DofMap::set_move(const std::string& group, const std::array<double, 3>& by) {
  const auto at = std::find(groups_.begin(), groups_.end(), group);
  if (at == groups_.end()) throw std::logic_error("DofMap::set_move: no boundary group " + group);
  moves_.resize(groups_.size(), {0, 0, 0});
  moves_[at - groups_.begin()] = by;
}

std::array<double, 3> DofMap::moved(const std::string& group) const {
  const auto at = std::find(groups_.begin(), groups_.end(), group);
  if (at == groups_.end() || moves_.empty()) return {0, 0, 0};
  return moves_[at - groups_.begin()];
}

void DofMap::apply(Vec u, double s) const {
  PetscScalar* a;
  HS_PETSC(VecGetArray(u, &a));
  for (int64_t l = 0; l < 3 * num_owned_; ++l)
    if (constrained_[l]) a[l] = prescribed_value(l, s);
  HS_PETSC(VecRestoreArray(u, &a));
}

void DofMap::set_rows(Vec u, double s, Vec R) const {
  PetscScalar* r;
  const PetscScalar* uo;
  HS_PETSC(VecGetArray(R, &r));
  HS_PETSC(VecGetArrayRead(u, &uo));
  for (int64_t l = 0; l < 3 * num_owned_; ++l)
    if (constrained_[l]) r[l] = uo[l] - prescribed_value(l, s);
  HS_PETSC(VecRestoreArrayRead(u, &uo));
  HS_PETSC(VecRestoreArray(R, &r));
}

void DofMap::zero(Vec v) const {
  PetscScalar* a;
  HS_PETSC(VecGetArray(v, &a));
  for (int64_t l = 0; l < 3 * num_owned_; ++l)
    if (constrained_[l]) a[l] = 0;
  HS_PETSC(VecRestoreArray(v, &a));
}

}  // namespace hs
