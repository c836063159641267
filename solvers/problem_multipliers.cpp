// The volume multipliers of exactly incompressible bodies (nu = 0.5; docs/formulation.md,
// "Exactly incompressible bodies"): one per patch of a nodal-pressure body
// (solvers/nodal_pressure.hpp), one per F-bar element, in that order in every vector here.
#include <mpi.h>

#include <algorithm>
#include <cmath>

#include "fem/element.hpp"
#include "materials/elastic_constants.hpp"
#include "solvers/problem.hpp"

namespace hs {

namespace {
size_t nodal_count(bool has, const Distribution& dist) {
  return has ? static_cast<size_t>(dist.num_local()) : 0;
}
}  // namespace

double Problem::largest_volume_change(Vec u) {
  LocalView view(u, u_work_);
  double largest = 0;
  if (has_nodal_volume_multipliers()) {
    nodal_->update(view.values(), nullptr);
    largest = nodal_->largest_volume_change();
  }
  if (fbar_lambda_.empty()) return largest;
  double local = 0, X[30], ue[30];
  for (size_t e = 0; e < fbar_lambda_.size(); ++e) {
    if (!fbar_incompressible_[e]) continue;
    element_coordinates(e, X);
    element_displacement(view.values(), e, ue);
    fbar_ln_Jbar_[e] = std::log1p(tet_volume_ratio_minus_one_fbar(dist_.order, X, ue));
    local = std::max(local, std::abs(fbar_ln_Jbar_[e]));
  }
  MPI_Allreduce(MPI_IN_PLACE, &local, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return std::max(largest, local);
}

std::vector<double> Problem::volume_multiplier_raise() const {
  std::vector<double> raise =
      has_nodal_volume_multipliers() ? nodal_->multiplier_raise() : std::vector<double>();
  for (size_t e = 0; e < fbar_lambda_.size(); ++e)
    raise.push_back(fbar_incompressible_[e] ? fbar_modulus_[dist_.tet_volume[e]] * fbar_ln_Jbar_[e]
                                            : 0.0);
  return raise;
}

std::vector<double> Problem::volume_multipliers() const {
  std::vector<double> lambda =
      has_nodal_volume_multipliers() ? nodal_->multipliers() : std::vector<double>();
  lambda.insert(lambda.end(), fbar_lambda_.begin(), fbar_lambda_.end());
  return lambda;
}

void Problem::set_volume_multipliers(const std::vector<double>& lambda) {
  const size_t n = nodal_count(has_nodal_volume_multipliers(), dist_);
  if (n) nodal_->set_multipliers(std::vector<double>(lambda.begin(), lambda.begin() + n));
  std::copy(lambda.begin() + n, lambda.end(), fbar_lambda_.begin());
}

void Problem::scale_fbar_penalty(double scale) {
  for (size_t v = 0; v < materials_.size(); ++v)
    if (fbar_rest_laws_[v] && hs::incompressible(materials_[v].law->elastic_constants()))
      fbar_modulus_[v] = scale * fbar_rest_laws_[v]->removed_modulus();
}

double Problem::multiplier_dot(const std::vector<double>& a, const std::vector<double>& b) const {
  const size_t n = nodal_count(has_nodal_volume_multipliers(), dist_);
  double sum = 0;
  for (int64_t k = 0; n && k < dist_.num_owned(); ++k) sum += a[k] * b[k];  // owned nodes
  for (size_t k = n; k < a.size(); ++k) sum += a[k] * b[k];                 // every local tet
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return sum;
}

void Problem::volume_multiplier_field(Vec field) const {
  const std::vector<double>& lambda = nodal_->multipliers();
  PetscScalar* a;
  HS_PETSC(VecGetArray(field, &a));
  for (int64_t n = 0; n < dist_.num_owned(); ++n) {
    a[3 * n] = lambda[n];
    a[3 * n + 1] = a[3 * n + 2] = 0;
  }
  HS_PETSC(VecRestoreArray(field, &a));
}

void Problem::set_volume_multipliers(Vec field) {
  LocalView view(field, u_work_);
  std::vector<double> lambda(dist_.num_local());
  for (int64_t n = 0; n < dist_.num_local(); ++n) lambda[n] = view.values()[3 * n];
  nodal_->set_multipliers(lambda);
}

}  // namespace hs
