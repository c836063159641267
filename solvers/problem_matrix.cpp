// Problem: the tangent's matrix and its pattern, its mixed system, the mass matrix.
#include <petsc/private/matimpl.h>  // Mat::nonzerostate (update_pattern)

#include <stdexcept>

#include "solvers/mixed_factor.hpp"
#include "solvers/problem.hpp"

namespace hs {

// Assembly by coordinates: every node-pair block (NodePairBlocks: the element and face
// matrices summed over the tetrahedra around the pair), Dirichlet diagonal and coupling block
// is one run of entries whose position PETSc resolves once (MatSetPreallocationCOO, which
// also communicates entries of rows owned elsewhere); each tangent then writes its values
// straight into that array and hands it over in one MatSetValuesCOO. Adding blocks one by one
// with MatSetValues searched the row of every entry again on every assembly: three times
// slower on the control step's tangent (docs/architecture.md, Assembly of the tangent).
void Problem::tangent_entries(std::vector<PetscInt>& rows, std::vector<PetscInt>& cols) const {
  rows.clear();
  cols.clear();
  auto block = [&](const PetscInt* idx, int n) {
    for (int r = 0; r < n; ++r)
      for (int c = 0; c < n; ++c) {
        rows.push_back(idx[r]);  // negative (Dirichlet) indices are ignored by PETSc
        cols.push_back(idx[c]);
      }
  };
  rows.reserve(9 * pairs_->num_pairs());
  cols.reserve(9 * pairs_->num_pairs());
  PetscInt row_idx[3], col_idx[3];
  for (int32_t a = 0; a < pairs_->num_nodes(); ++a) {
    dofs_.indices(&a, 1, row_idx);
    for (int64_t k = pairs_->offset(a); k < pairs_->offset(a + 1); ++k) {
      const int32_t b = pairs_->column(k);
      dofs_.indices(&b, 1, col_idx);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          rows.push_back(row_idx[r]);
          cols.push_back(col_idx[c]);
        }
    }
  }
  for (int64_t l = 0; l < dofs_.num_owned_dofs(); ++l)
    if (dofs_.constrained(l)) {
      rows.push_back(dofs_.global(l));
      cols.push_back(dofs_.global(l));
    }
  for (const auto& dofs : couplings_) block(dofs.data(), static_cast<int>(dofs.size()));
  if (!self_contact_) return;
  int64_t r[3], c[3];
  for (size_t k = 0; k < self_contact_->pattern().size(); ++k) {
    self_contact_->pattern_dofs(k, r, c);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        rows.push_back(static_cast<PetscInt>(r[i]));
        cols.push_back(static_cast<PetscInt>(c[j]));
      }
  }
}

void Problem::pattern_entries(std::vector<PetscInt>& rows, std::vector<PetscInt>& cols) {
  tangent_entries(rows, cols);
  if (nodal_) nodal_->coupling_entries(rows, cols);  // last: jacobian() fills them at the end
  tangent_values_.assign(rows.size(), 0.0);
}

// A matrix preallocated again in place kept parts of its old layout on 2 ranks (MUMPS then
// failed), so the new pattern is a new matrix whose data replace J's under J's handle, which
// the solvers hold. Its nonzero state, which PCSetUp compares to decide that a direct
// solver's analysis must be redone, is moved past the old one's; so is the mixed system's.
void Problem::update_pattern(Mat J) {
  const auto known = matrix_pattern_.find(J);
  if (known == matrix_pattern_.end() || known->second == pattern_version_) return;
  PetscObject old_mixed = nullptr;
  if (nodal_)
    HS_PETSC(PetscObjectQuery(reinterpret_cast<PetscObject>(J), kMixedTangentKey, &old_mixed));
  const PetscObjectState state = J->nonzerostate;
  const PetscObjectState mixed_state =
      old_mixed ? reinterpret_cast<Mat>(old_mixed)->nonzerostate : 0;
  Mat fresh = create_pattern_matrix();
  matrix_pattern_.erase(fresh);
  MatHandle mixed;
  if (old_mixed) {
    mixed_rows_.clear();
    mixed = MatHandle(create_mixed_matrix());
    mixed.get()->nonzerostate = mixed_state + 1;
  }
  HS_PETSC(MatHeaderReplace(J, &fresh));
  J->nonzerostate = state + 1;
  if (old_mixed)
    HS_PETSC(PetscObjectCompose(reinterpret_cast<PetscObject>(J), kMixedTangentKey,
                                reinterpret_cast<PetscObject>(mixed.get())));
  matrix_pattern_[J] = pattern_version_;
}

int Problem::add_coupling(std::vector<PetscInt> dofs) {
  if (pattern_fixed_)
    throw std::logic_error("Problem::add_coupling after the tangent's matrix was created");
  coupling_values_.emplace_back(dofs.size() * dofs.size(), 0.0);
  couplings_.push_back(std::move(dofs));
  return static_cast<int>(couplings_.size()) - 1;
}

void Problem::set_coupling(int k, const std::vector<PetscScalar>& values) {
  if (values.size() != coupling_values_.at(k).size())
    throw std::logic_error("Problem::set_coupling: wrong number of values");
  coupling_values_[k] = values;
}

void Problem::fill_constraint_entries(PetscScalar* value) const {
  for (int64_t l = 0; l < dofs_.num_owned_dofs(); ++l)
    if (dofs_.constrained(l)) *value++ = 1.0;
  for (const auto& block : coupling_values_) value = std::copy(block.begin(), block.end(), value);
}

Mat Problem::create_matrix(bool mixed) {
  MatHandle A(create_pattern_matrix());  // the caller's once returned
  if (nodal_ && mixed) {
    MatHandle mixed(create_mixed_matrix());
    HS_PETSC(PetscObjectCompose(reinterpret_cast<PetscObject>(A.get()), kMixedTangentKey,
                                reinterpret_cast<PetscObject>(mixed.get())));
  }
  return A.release();
}

Mat Problem::create_mixed_matrix() {
  MatHandle A;  // the caller's once returned
  const PetscInt n = nodal_->mixed_local_size();
  HS_PETSC(MatCreate(comm_, A.out()));
  HS_PETSC(MatSetSizes(A, n, n, PETSC_DETERMINE, PETSC_DETERMINE));
  HS_PETSC(MatSetType(A, MATAIJ));
  preallocate_mixed(A);
  return A.release();
}

void Problem::preallocate_mixed(Mat A) {
  if (mixed_rows_.empty()) {
    std::vector<PetscInt> rows, cols;
    tangent_entries(rows, cols);
    for (auto* index : {&rows, &cols})
      for (PetscInt& i : *index) i = nodal_->mixed_dof(i);
    nodal_->mixed_entries(rows, cols);
    mixed_rows_ = std::move(rows);
    mixed_cols_ = std::move(cols);
    mixed_values_.assign(mixed_rows_.size(), 0.0);
  }
  std::vector<PetscInt> rows = mixed_rows_, cols = mixed_cols_;  // PETSc may change them
  HS_PETSC(
      MatSetPreallocationCOO(A, static_cast<PetscCount>(rows.size()), rows.data(), cols.data()));
}

// The tangent less the patch coupling (its values come last in tangent_values_), with the
// inertia term as the tangent has it, then G, G^T and -D^-1.
void Problem::fill_mixed_matrix(Mat mixed) {
  const size_t tangent = tangent_values_.size() - nodal_->num_coupling_entries();
  std::copy(tangent_values_.begin(), tangent_values_.begin() + tangent, mixed_values_.begin());
  if (inertia_) {  // the mass matrix's values come first; self-contact's pattern may have grown
    if (mass_values_.empty())
      throw std::logic_error("Problem: inertia with a mass matrix not made by this problem");
    for (size_t k = 0; k < std::min(tangent, mass_values_.size()); ++k)
      mixed_values_[k] += inertia_->c * mass_values_[k];
  }
  nodal_->fill_mixed(mixed_values_.data() + tangent);
  HS_PETSC(MatSetValuesCOO(mixed, mixed_values_.data(), INSERT_VALUES));
}

Mat Problem::create_pattern_matrix() {
  pattern_fixed_ = true;
  const int64_t nowned = dist_.num_owned();
  if (!pairs_) pairs_ = std::make_unique<NodePairBlocks>(dist_.tet_nodes, npe_, dist_.num_local());
  std::vector<PetscInt> rows, cols;
  pattern_entries(rows, cols);
  MatHandle A;  // the caller's once returned
  HS_PETSC(MatCreate(comm_, A.out()));
  HS_PETSC(MatSetSizes(A, 3 * nowned, 3 * nowned, PETSC_DETERMINE, PETSC_DETERMINE));
  HS_PETSC(MatSetBlockSize(A, 3));
  HS_PETSC(MatSetType(A, MATAIJ));
  HS_PETSC(MatSetFromOptions(A));
  HS_PETSC(
      MatSetPreallocationCOO(A, static_cast<PetscCount>(rows.size()), rows.data(), cols.data()));

  // Rigid-body modes from the reference coordinates of the owned nodes.
  VecHandle coords;
  HS_PETSC(VecCreateMPI(comm_, 3 * nowned, PETSC_DETERMINE, coords.out()));
  HS_PETSC(VecSetBlockSize(coords, 3));
  PetscScalar* c;
  HS_PETSC(VecGetArray(coords, &c));
  for (int64_t i = 0; i < 3 * nowned; ++i) c[i] = X_[i];
  HS_PETSC(VecRestoreArray(coords, &c));
  NullSpaceHandle nullspace;
  HS_PETSC(MatNullSpaceCreateRigidBody(coords, nullspace.out()));
  HS_PETSC(MatSetNearNullSpace(A, nullspace));
  matrix_pattern_[A.get()] = pattern_version_;
  return A.release();
}

// The consistent mass matrix in the tangent's pattern (element blocks, unit diagonal on
// Dirichlet rows, zero elsewhere), by coordinates like the tangent.
Mat Problem::create_mass_matrix() {
  MatHandle M(create_pattern_matrix());  // the caller's once returned
  std::vector<PetscScalar>& values = mass_values_;
  values.assign(tangent_values_.size(), 0.0);
  double X[30], Me[900];
  for (size_t e = 0; e < dist_.local_tets.size(); ++e) {
    element_coordinates(e, X);
    const auto& m = materials_[dist_.tet_volume[e]];
    tet_mass(dist_.order, X, m.density, Me);
    pairs_->add_tet(static_cast<int64_t>(e), Me, values.data());
  }
  PetscScalar* value = values.data() + 9 * pairs_->num_pairs();
  for (int64_t l = 0; l < dofs_.num_owned_dofs(); ++l)
    if (dofs_.constrained(l)) *value++ = 1.0;
  HS_PETSC(MatSetValuesCOO(M, values.data(), INSERT_VALUES));
  return M.release();
}

void Problem::reset_if_pattern_grew(KSP ksp, int& seen) const {
  if (pattern_version_ == seen) return;
  seen = pattern_version_;
  PC pc;
  HS_PETSC(KSPGetPC(ksp, &pc));
  HS_PETSC(PCReset(pc));
}

}  // namespace hs
