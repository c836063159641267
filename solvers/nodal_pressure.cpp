#include "solvers/nodal_pressure.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "materials/volumetric_term.hpp"
#include "solvers/petsc_check.hpp"

namespace hs {

NodalPressure::NodalPressure(const Distribution& dist, const std::vector<P1Geometry>& geometry,
                             std::vector<double> modulus, const std::vector<char>& incompressible,
                             bool small_strain, const DofMap& dofs, MPI_Comm comm)
    : dist_(dist),
      geometry_(geometry),
      modulus_(std::move(modulus)),
      small_strain_(small_strain),
      comm_(comm) {
  const int64_t nl = dist.num_local(), no = dist.num_owned();
  std::vector<PetscInt> ghosts(dist.local_nodes.begin() + no, dist.local_nodes.end());
  HS_PETSC(VecCreateGhost(comm, static_cast<PetscInt>(no), PETSC_DETERMINE,
                          static_cast<PetscInt>(ghosts.size()), ghosts.data(), patch_sum_.out()));
  V_.assign(nl, 0.0);
  kV_.assign(nl, 0.0);
  for (size_t e = 0; e < modulus_.size(); ++e) {
    if (!takes_part(e)) continue;
    for (int a = 0; a < 4; ++a) {
      const int32_t n = dist.tet_nodes[4 * e + a];
      V_[n] += geometry_[e].volume / 4;
      kV_[n] += modulus_[e] * geometry_[e].volume / 4;
    }
  }
  std::vector<double> compressible(nl, 0.0);  // per node: its patch's compressible volume
  for (size_t e = 0; e < modulus_.size(); ++e)
    if (takes_part(e) && !incompressible[e])
      for (int a = 0; a < 4; ++a) compressible[dist.tet_nodes[4 * e + a]] += geometry_[e].volume;
  sum_over_patches(V_);
  sum_over_patches(kV_);
  sum_over_patches(compressible);
  lambda_.assign(nl, 0.0);
  multiplied_.assign(nl, 0);
  int any = 0;
  for (int64_t n = 0; n < nl; ++n) {
    multiplied_[n] = V_[n] > 0 && compressible[n] == 0;
    any |= multiplied_[n];
  }
  MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, comm);
  has_multipliers_ = any;
  dof_index_.resize(3 * nl);
  for (int32_t n = 0; n < nl; ++n) dofs.indices(&n, 1, &dof_index_[3 * n]);
  dv_.assign(nl, 0.0);
  p_.assign(nl, 0.0);
  c_.assign(nl, 0.0);
}

void NodalPressure::sum_over_patches(std::vector<double>& local_values) {
  Vec local;
  PetscScalar* a;
  HS_PETSC(VecGhostGetLocalForm(patch_sum_, &local));
  HS_PETSC(VecGetArray(local, &a));
  std::copy(local_values.begin(), local_values.end(), a);
  HS_PETSC(VecRestoreArray(local, &a));
  HS_PETSC(VecGhostRestoreLocalForm(patch_sum_, &local));
  HS_PETSC(VecGhostUpdateBegin(patch_sum_, ADD_VALUES, SCATTER_REVERSE));
  HS_PETSC(VecGhostUpdateEnd(patch_sum_, ADD_VALUES, SCATTER_REVERSE));
  HS_PETSC(VecGhostUpdateBegin(patch_sum_, INSERT_VALUES, SCATTER_FORWARD));
  HS_PETSC(VecGhostUpdateEnd(patch_sum_, INSERT_VALUES, SCATTER_FORWARD));
  HS_PETSC(VecGhostGetLocalForm(patch_sum_, &local));
  HS_PETSC(VecGetArray(local, &a));
  std::copy(a, a + local_values.size(), local_values.begin());
  HS_PETSC(VecRestoreArray(local, &a));
  HS_PETSC(VecGhostRestoreLocalForm(patch_sum_, &local));
}

namespace {
void element_displacement(const Distribution& dist, const PetscScalar* u_local, size_t e,
                          double* ue) {
  for (int a = 0; a < 4; ++a)
    for (int d = 0; d < 3; ++d) ue[3 * a + d] = u_local[3 * dist.tet_nodes[4 * e + a] + d];
}
}  // namespace

bool NodalPressure::update(const PetscScalar* u_local, int64_t* bad_tet) {
  std::fill(dv_.begin(), dv_.end(), 0.0);
  double ue[12];
  for (size_t e = 0; e < modulus_.size(); ++e) {
    if (!takes_part(e)) continue;
    element_displacement(dist_, u_local, e, ue);
    const double change = p1_volume_change(geometry_[e], ue, nullptr, nullptr, small_strain_);
    for (int a = 0; a < 4; ++a) dv_[dist_.tet_nodes[4 * e + a]] += change / 4;
  }
  sum_over_patches(dv_);
  bool ok = true;
  for (size_t n = 0; n < V_.size(); ++n) {
    p_[n] = c_[n] = 0;
    if (!(V_[n] > 0)) continue;
    const double J_minus_one = dv_[n] / V_[n];
    if (!small_strain_ && !(1.0 + J_minus_one > 0)) {
      ok = false;
      continue;
    }
    const VolumetricValues U1 = volumetric_function(1.0, J_minus_one, small_strain_);
    p_[n] = kV_[n] * U1.dU / V_[n];
    c_[n] = kV_[n] * U1.d2U / (V_[n] * V_[n]);
    if (lambda_[n] != 0) {  // + lambda_a M(J_a): M' = 1/J, M'' = -1/J^2 (1 and 0, small strains)
      const double dM = small_strain_ ? 1.0 : 1.0 / (1.0 + J_minus_one);
      p_[n] += lambda_[n] * dM;
      if (!small_strain_) c_[n] -= lambda_[n] * dM * dM / V_[n];
    }
  }
  tangent_p_ = p_;
  if (!ok && bad_tet)
    for (size_t e = 0; e < modulus_.size() && *bad_tet < 0; ++e)
      for (int a = 0; a < 4; ++a) {
        const int32_t n = dist_.tet_nodes[4 * e + a];
        if (takes_part(e) && !(1.0 + dv_[n] / V_[n] > 0)) *bad_tet = static_cast<int64_t>(e);
      }
  return ok;
}

// With U1 = (ln J)^2 / 2 and q the Kirchhoff pressure kbar ln J, the tangent's terms are
//   p_a = q_a / J_a (the Cauchy pressure in the element part),
//   c_a = (kbar_a - q_a) / (V_a J_a^2) = kV_a U1''(J_a) / V_a^2 when q_a = kbar_a ln J_a,
// and the mixed Newton's q_a is kbar_a (ln J_a(u0) + g_a(u0) . (u - u0) / v_a(u0)), u0 the
// previous tangent's point.
void NodalPressure::linearize(const PetscScalar* u_local) {
  if (small_strain_) return;  // linear: the tangent does not depend on u
  const size_t nl = V_.size();
  // An inverted patch (the tangent is refused) is no point to linearise from, on any rank.
  int valid = 1;
  for (size_t n = 0; n < nl; ++n)
    if (V_[n] > 0 && !(1.0 + dv_[n] / V_[n] > 0)) valid = 0;
  MPI_Allreduce(MPI_IN_PLACE, &valid, 1, MPI_INT, MPI_MIN, comm_);
  if (!valid) {
    lin_.valid = false;
    return;
  }
  if (lin_.valid) {
    std::vector<double> dv_lin(nl, 0.0);  // g_a(u0) . (u - u0), summed over the patches
    for (size_t e = 0; e < modulus_.size(); ++e) {
      if (!takes_part(e)) continue;
      double change = 0;
      for (int a = 0; a < 4; ++a) {
        const int32_t n = dist_.tet_nodes[4 * e + a];
        for (int d = 0; d < 3; ++d)
          change += lin_.grad[12 * e + 3 * a + d] * (u_local[3 * n + d] - lin_.u[3 * n + d]);
      }
      for (int a = 0; a < 4; ++a) dv_lin[dist_.tet_nodes[4 * e + a]] += change / 4;
    }
    sum_over_patches(dv_lin);
    for (size_t n = 0; n < nl; ++n) {
      if (!(V_[n] > 0)) continue;
      const double lnJ = lin_.lnJ[n] + dv_lin[n] / lin_.v[n];
      const double J = 1.0 + dv_[n] / V_[n], kbar = kV_[n] / V_[n];
      tangent_p_[n] = (lambda_[n] + kbar * lnJ) / J;
      c_[n] = (kbar * (1.0 - lnJ) - lambda_[n]) / (V_[n] * J * J);
    }
  }
  lin_.valid = true;
  lin_.u.assign(u_local, u_local + 3 * nl);
  lin_.lnJ.assign(nl, 0.0);
  lin_.v.assign(nl, 0.0);
  for (size_t n = 0; n < nl; ++n)
    if (V_[n] > 0) {
      lin_.lnJ[n] = std::log1p(dv_[n] / V_[n]);
      lin_.v[n] = V_[n] + dv_[n];
    }
  lin_.grad.assign(12 * modulus_.size(), 0.0);
  double ue[12];
  for (size_t e = 0; e < modulus_.size(); ++e) {
    if (!takes_part(e)) continue;
    element_displacement(dist_, u_local, e, ue);
    p1_volume_change(geometry_[e], ue, &lin_.grad[12 * e], nullptr);
  }
}

bool NodalPressure::patch_term(int32_t n, const std::vector<int64_t>& elements,
                               const PetscScalar* ua, PatchTerm& term, double* grad,
                               double* hess) const {
  double ue[12], change = 0;
  for (size_t i = 0; i < elements.size(); ++i) {
    element_displacement(dist_, ua, static_cast<size_t>(elements[i]), ue);
    change += p1_volume_change(geometry_[elements[i]], ue, grad + 12 * i,
                               hess ? hess + 144 * i : nullptr, small_strain_) /
              4;
  }
  if (!(V_[n] > 0)) return false;
  const double J_minus_one = change / V_[n];
  if (!small_strain_ && !(1.0 + J_minus_one > 0)) return false;
  const VolumetricValues U1 = volumetric_function(1.0, J_minus_one, small_strain_);
  term.energy = kV_[n] * U1.U;
  term.p = kV_[n] * U1.dU / V_[n];
  term.c = kV_[n] * U1.d2U / (V_[n] * V_[n]);
  return std::isfinite(term.p) && std::isfinite(term.c);
}

std::vector<std::vector<int64_t>> NodalPressure::patch_elements() const {
  std::vector<std::vector<int64_t>> patches(V_.size());
  for (size_t e = 0; e < modulus_.size(); ++e)
    if (takes_part(e))
      for (int a = 0; a < 4; ++a) patches[dist_.tet_nodes[4 * e + a]].push_back(e);
  return patches;
}

double NodalPressure::element_pressure(int64_t e) const {
  double sum = 0;
  for (int a = 0; a < 4; ++a) sum += p_[dist_.tet_nodes[4 * e + a]];
  return sum / 4;
}

void NodalPressure::add_element(int64_t e, const double* ue, double* r, double* K) const {
  double grad[12], hess[144];
  p1_volume_change(geometry_[e], ue, grad, K ? hess : nullptr, small_strain_);
  const double p = element_pressure(e);
  for (int k = 0; k < 12; ++k) r[k] += p * grad[k];
  if (!K) return;
  double q = 0;
  for (int a = 0; a < 4; ++a) q += tangent_p_[dist_.tet_nodes[4 * e + a]] / 4;
  for (int k = 0; k < 144; ++k) K[k] += q * hess[k];
}

void NodalPressure::add_element_scale(int64_t e, const double* ue, double* K) const {
  double grad[12];
  p1_volume_change(geometry_[e], ue, grad, nullptr, small_strain_);
  const double c = modulus_[e] / geometry_[e].volume;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) K[12 * i + j] += c * grad[i] * grad[j];
}

double NodalPressure::owned_energy() const {
  double sum = 0;
  for (int64_t n = 0; n < dist_.num_owned(); ++n)
    if (V_[n] > 0)
      sum += kV_[n] * volumetric_function(1.0, dv_[n] / V_[n], small_strain_).U +
             V_[n] * lambda_[n] * volume_measure(n);
  return sum;
}

double NodalPressure::volume_measure(size_t n) const {
  return small_strain_ ? dv_[n] / V_[n] : std::log1p(dv_[n] / V_[n]);
}

double NodalPressure::largest_volume_change() const {
  double largest = 0;
  for (int64_t n = 0; n < dist_.num_owned(); ++n)
    if (multiplied_[n]) largest = std::max(largest, std::abs(volume_measure(n)));
  MPI_Allreduce(MPI_IN_PLACE, &largest, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return largest;
}

std::vector<double> NodalPressure::multiplier_raise() const {
  std::vector<double> raise(V_.size(), 0.0);
  for (size_t n = 0; n < V_.size(); ++n)
    if (multiplied_[n]) raise[n] = kV_[n] / V_[n] * volume_measure(n);
  return raise;
}

void NodalPressure::coupling_entries(std::vector<PetscInt>& rows, std::vector<PetscInt>& cols) {
  if (!coupling_) make_coupling();
  rows.insert(rows.end(), coupling_rows_.begin(), coupling_rows_.end());
  cols.insert(cols.end(), coupling_cols_.begin(), coupling_cols_.end());
}

void NodalPressure::make_coupling() {
  const PetscInt no = static_cast<PetscInt>(dist_.num_owned());
  const PetscInt first = static_cast<PetscInt>(dist_.owned_offsets[dist_.rank]);
  // G: a row per node, a column per dof; every element adds its dv_e/du / 4 to its nodes' rows.
  std::vector<PetscInt> gr, gc;
  for (size_t e = 0; e < modulus_.size(); ++e) {
    if (!takes_part(e)) continue;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        for (int i = 0; i < 3; ++i) {
          gr.push_back(static_cast<PetscInt>(dist_.local_nodes[dist_.tet_nodes[4 * e + a]]));
          gc.push_back(dof_index_[3 * dist_.tet_nodes[4 * e + b] + i]);
        }
  }
  g_values_.assign(gr.size(), 0.0);
  g_rows_ = gr;  // PETSc may change the arrays it is given
  g_cols_ = gc;
  HS_PETSC(MatCreate(comm_, G_.out()));
  HS_PETSC(MatSetSizes(G_, no, 3 * no, PETSC_DETERMINE, PETSC_DETERMINE));
  HS_PETSC(MatSetType(G_, MATAIJ));
  HS_PETSC(MatSetPreallocationCOO(G_, static_cast<PetscCount>(gr.size()), gr.data(), gc.data()));
  HS_PETSC(MatSetValuesCOO(G_, g_values_.data(), INSERT_VALUES));
  std::vector<PetscInt> diagonal(no);
  for (PetscInt n = 0; n < no; ++n) diagonal[n] = first + n;
  HS_PETSC(MatCreate(comm_, D_.out()));
  HS_PETSC(MatSetSizes(D_, no, no, PETSC_DETERMINE, PETSC_DETERMINE));
  HS_PETSC(MatSetType(D_, MATAIJ));
  HS_PETSC(MatSetPreallocationCOO(D_, no, diagonal.data(), diagonal.data()));
  std::vector<PetscScalar> ones(no, 1.0);
  HS_PETSC(MatSetValuesCOO(D_, ones.data(), INSERT_VALUES));
  HS_PETSC(MatPtAP(D_, G_, MAT_INITIAL_MATRIX, PETSC_DEFAULT, coupling_.out()));
  PetscInt begin, end;
  HS_PETSC(MatGetOwnershipRange(coupling_, &begin, &end));
  for (PetscInt row = begin; row < end; ++row) {
    PetscInt n;
    const PetscInt* c;
    HS_PETSC(MatGetRow(coupling_, row, &n, &c, nullptr));
    for (PetscInt k = 0; k < n; ++k) {
      coupling_rows_.push_back(row);
      coupling_cols_.push_back(c[k]);
    }
    coupling_row_sizes_.push_back(n);
    HS_PETSC(MatRestoreRow(coupling_, row, &n, &c, nullptr));
  }
}

void NodalPressure::fill_coupling(const PetscScalar* u_local, PetscScalar* values) {
  double ue[12], grad[12];
  PetscScalar* g = g_values_.data();
  for (size_t e = 0; e < modulus_.size(); ++e) {
    if (!takes_part(e)) continue;
    element_displacement(dist_, u_local, e, ue);
    p1_volume_change(geometry_[e], ue, grad, nullptr, small_strain_);
    for (int a = 0; a < 4; ++a)
      for (int k = 0; k < 12; ++k) *g++ = grad[k] / 4;
  }
  HS_PETSC(MatSetValuesCOO(G_, g_values_.data(), INSERT_VALUES));
  HS_PETSC(MatSetValuesCOO(D_, c_.data(), INSERT_VALUES));  // owned nodes come first
  Mat coupling = coupling_;                                 // refilled in place
  HS_PETSC(MatPtAP(D_, G_, MAT_REUSE_MATRIX, PETSC_DEFAULT, &coupling));
  PetscInt begin, end;
  HS_PETSC(MatGetOwnershipRange(coupling_, &begin, &end));
  for (PetscInt row = begin; row < end; ++row) {
    PetscInt n;
    const PetscScalar* v;
    HS_PETSC(MatGetRow(coupling_, row, &n, nullptr, &v));
    if (n != coupling_row_sizes_[row - begin])
      throw std::logic_error("NodalPressure: the patch coupling's pattern changed");
    values = std::copy(v, v + n, values);
    HS_PETSC(MatRestoreRow(coupling_, row, &n, nullptr, &v));
  }
}

PetscInt NodalPressure::mixed_dof(PetscInt dof) const {
  if (dof < 0) return dof;
  const auto& off = dist_.owned_offsets;
  const auto r = std::upper_bound(off.begin(), off.end(), dof / 3) - off.begin() - 1;
  return dof + static_cast<PetscInt>(off[r]);
}

PetscInt NodalPressure::mixed_node(PetscInt node) const {
  const auto& off = dist_.owned_offsets;
  const auto r = std::upper_bound(off.begin(), off.end(), node) - off.begin() - 1;
  return node + 3 * static_cast<PetscInt>(off[r + 1]);
}

void NodalPressure::mixed_entries(std::vector<PetscInt>& rows, std::vector<PetscInt>& cols) {
  if (!coupling_) make_coupling();
  const size_t n = g_rows_.size();
  std::vector<PetscInt> pressure(n), displacement(n);
  for (size_t k = 0; k < n; ++k) {
    pressure[k] = mixed_node(g_rows_[k]);
    displacement[k] = mixed_dof(g_cols_[k]);
  }
  rows.insert(rows.end(), pressure.begin(), pressure.end());
  cols.insert(cols.end(), displacement.begin(), displacement.end());
  rows.insert(rows.end(), displacement.begin(), displacement.end());
  cols.insert(cols.end(), pressure.begin(), pressure.end());
  const int64_t first = dist_.owned_offsets[dist_.rank];
  for (int64_t a = 0; a < dist_.num_owned(); ++a) {
    rows.push_back(mixed_node(static_cast<PetscInt>(first + a)));
    cols.push_back(rows.back());
  }
}

void NodalPressure::fill_mixed(PetscScalar* values) const {
  values = std::copy(g_values_.begin(), g_values_.end(), values);
  values = std::copy(g_values_.begin(), g_values_.end(), values);
  // c_a is 0 only at nodes of no nodal-pressure body (V_a = 0, G's row empty), or of an
  // inverted patch, whose tangent is refused.
  for (int64_t a = 0; a < dist_.num_owned(); ++a) *values++ = c_[a] != 0 ? -1.0 / c_[a] : -1.0;
}

}  // namespace hs
