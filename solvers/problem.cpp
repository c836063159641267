#include "solvers/problem.hpp"

#include <petscsys.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.hpp"
#include "fem/element.hpp"

namespace hs {

Problem::Problem(const Config& config, const Mesh& mesh, const Distribution& dist, MPI_Comm comm,
                 ExactDirichlet exact)
    : comm_(comm),
      mesh_(mesh),
      dist_(dist),
      npe_(mesh.nodes_per_tet()),
      exact_(std::move(exact)) {
  // Materials per volume group of the mesh.
  materials_.resize(mesh.volume_names.size());
  std::vector<char> has_material(mesh.volume_names.size(), 0);
  for (const auto& mc : config.materials) {
    auto it = std::find(mesh.volume_names.begin(), mesh.volume_names.end(), mc.group);
    if (it == mesh.volume_names.end())
      throw InputError("material group '" + mc.group + "' is not a volume");
    const auto v = static_cast<size_t>(it - mesh.volume_names.begin());
    materials_[v] = mc;
    has_material[v] = 1;
  }
  for (size_t v = 0; v < has_material.size(); ++v)
    if (!has_material[v])
      throw InputError("volume group '" + mesh.volume_names[v] + "' has no material");

  const int64_t nlocal = dist.num_local();
  X_local_.resize(3 * nlocal);
  for (int64_t i = 0; i < nlocal; ++i)
    for (int d = 0; d < 3; ++d) X_local_[3 * i + d] = mesh.x[3 * dist.old_of_local[i] + d];

  global_dof_.resize(3 * nlocal);
  for (int64_t i = 0; i < nlocal; ++i)
    for (int d = 0; d < 3; ++d)
      global_dof_[3 * i + d] = static_cast<PetscInt>(3 * dist.local_nodes[i] + d);
  for (int64_t i = dist.num_owned(); i < nlocal; ++i)
    ghost_blocks_.push_back(static_cast<PetscInt>(dist.local_nodes[i]));

  // Dirichlet data per local dof (a later condition on the same dof wins).
  constrained_.assign(3 * nlocal, 0);
  prescribed_.assign(3 * nlocal, 0.0);
  scaled_.assign(3 * nlocal, 1);
  from_exact_.assign(3 * nlocal, 0);
  for (const auto& bc : config.dirichlet) {
    if (bc.exact && !exact_)
      throw InputError(config.deck_path + ": boundary: group '" + bc.group +
                       "' asks for exact values but the deck has no exact solution");
    auto it = dist.node_groups.find(bc.group);
    if (it == dist.node_groups.end()) continue;  // group has no node on this rank
    for (int32_t n : it->second)
      for (int d = 0; d < 3; ++d)
        if (bc.components[d]) {
          constrained_[3 * n + d] = 1;
          prescribed_[3 * n + d] = bc.value[d];
          scaled_[3 * n + d] = bc.scaled;
          from_exact_[3 * n + d] = bc.exact;
        }
  }

  // Body force per local tet at full load.
  const auto nt = dist.local_tets.size();
  body_force_.assign(nt * 3 * npe_, 0.0);
  std::vector<double> X(3 * npe_);
  for (size_t e = 0; e < nt; ++e) {
    element_coordinates(e, X.data());
    const auto& m = materials_[mesh.tet_volume[dist.local_tets[e]]];
    tet_body_force(mesh.order, X.data(), m.density, config.gravity, &body_force_[e * 3 * npe_]);
    if (mesh.order == 1) p1_geometry_.push_back(tet_p1_geometry(X.data()));
  }

  for (const auto& pc : config.pressures) {
    auto it = dist.faces.find(pc.group);
    PressureSurface s;
    s.value = pc.value;
    if (it != dist.faces.end()) s.faces = it->second;
    pressure_faces_.push_back(std::move(s));
  }
  bool any_faces = false;
  for (const auto& s : pressure_faces_) any_faces |= !s.faces.empty();
  int local_any = any_faces, global_any = 0;
  MPI_Allreduce(&local_any, &global_any, 1, MPI_INT, MPI_MAX, comm_);
  if (!global_any) pressure_faces_.clear();

  u_work_ = create_vector();
  HS_PETSC(VecDuplicate(u_work_, &r_work_));
}

Problem::~Problem() {
  VecDestroy(&u_work_);
  VecDestroy(&r_work_);
}

Vec Problem::create_vector() const {
  Vec v;
  HS_PETSC(VecCreateGhostBlock(comm_, 3, 3 * static_cast<PetscInt>(dist_.num_owned()), PETSC_DECIDE,
                               static_cast<PetscInt>(ghost_blocks_.size()), ghost_blocks_.data(),
                               &v));
  HS_PETSC(VecSet(v, 0.0));
  return v;
}

void Problem::element_coordinates(int64_t e, double* X) const {
  const int32_t* nodes = &dist_.tet_nodes[e * npe_];
  for (int a = 0; a < npe_; ++a)
    for (int d = 0; d < 3; ++d) X[3 * a + d] = X_local_[3 * nodes[a] + d];
}

ElementOutput Problem::element_force(int64_t e, const PetscScalar* ua, double* r, double* K) const {
  double X[30], ue[30];
  element_displacement(ua, e, ue);
  const auto& m = materials_[mesh_.tet_volume[dist_.local_tets[e]]];
  if (!p1_geometry_.empty()) return tet_internal_force_p1(p1_geometry_[e], ue, *m.law, r, K);
  element_coordinates(e, X);
  return tet_internal_force(mesh_.order, X, ue, *m.law, r, K);
}

void Problem::element_displacement(const PetscScalar* u_local, int64_t e, double* u) const {
  const int32_t* nodes = &dist_.tet_nodes[e * npe_];
  for (int a = 0; a < npe_; ++a)
    for (int d = 0; d < 3; ++d) u[3 * a + d] = u_local[3 * nodes[a] + d];
}

void Problem::dof_indices(int64_t e, PetscInt* idx) const {
  const int32_t* nodes = &dist_.tet_nodes[e * npe_];
  face_dofs(nodes, npe_, idx);
}

void Problem::face_dofs(const int32_t* nodes, int n, PetscInt* idx) const {
  for (int a = 0; a < n; ++a)
    for (int d = 0; d < 3; ++d) {
      const auto l = 3 * static_cast<int64_t>(nodes[a]) + d;
      idx[3 * a + d] = constrained_[l] ? -1 : global_dof_[l];
    }
}

// Assembly by coordinates: every element, face, Dirichlet diagonal and coupling block is one
// run of entries whose position PETSc resolves once (MatSetPreallocationCOO, which also
// communicates entries of rows owned elsewhere); each tangent then writes its values straight
// into that array and hands it over in one MatSetValuesCOO. Adding blocks one by one with
// MatSetValues searched the row of every entry again on every assembly: three times slower on
// the control step's tangent (docs/architecture.md, Assembly of the tangent).
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
  PetscInt idx[30];
  for (size_t e = 0; e < dist_.local_tets.size(); ++e) {
    dof_indices(e, idx);
    block(idx, 3 * npe_);
  }
  const int npf = mesh_.nodes_per_face();
  for (const auto& surface : pressure_faces_)
    for (size_t f = 0; f < surface.faces.size() / npf; ++f) {
      face_dofs(&surface.faces[f * npf], npf, idx);
      block(idx, 3 * npf);
    }
  for (int64_t l = 0; l < 3 * dist_.num_owned(); ++l)
    if (constrained_[l]) {
      rows.push_back(global_dof_[l]);
      cols.push_back(global_dof_[l]);
    }
  for (const auto& dofs : couplings_) block(dofs.data(), static_cast<int>(dofs.size()));
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

size_t Problem::num_face_entries() const {
  const size_t nf = 3 * mesh_.nodes_per_face();
  size_t faces = 0;
  for (const auto& surface : pressure_faces_) faces += surface.faces.size() / (nf / 3);
  return faces * nf * nf;
}

void Problem::fill_constraint_entries(PetscScalar* value) const {
  for (int64_t l = 0; l < 3 * dist_.num_owned(); ++l)
    if (constrained_[l]) *value++ = 1.0;
  for (const auto& block : coupling_values_) value = std::copy(block.begin(), block.end(), value);
}

Mat Problem::create_matrix() {
  pattern_fixed_ = true;
  const int64_t nowned = dist_.num_owned();
  std::vector<PetscInt> rows, cols;
  tangent_entries(rows, cols);
  tangent_values_.assign(rows.size(), 0.0);
  Mat A;
  HS_PETSC(MatCreate(comm_, &A));
  HS_PETSC(MatSetSizes(A, 3 * nowned, 3 * nowned, PETSC_DETERMINE, PETSC_DETERMINE));
  HS_PETSC(MatSetBlockSize(A, 3));
  HS_PETSC(MatSetType(A, MATAIJ));
  HS_PETSC(MatSetFromOptions(A));
  HS_PETSC(
      MatSetPreallocationCOO(A, static_cast<PetscCount>(rows.size()), rows.data(), cols.data()));

  // Rigid-body modes from the reference coordinates of the owned nodes.
  Vec coords;
  HS_PETSC(VecCreateMPI(comm_, 3 * nowned, PETSC_DETERMINE, &coords));
  HS_PETSC(VecSetBlockSize(coords, 3));
  PetscScalar* c;
  HS_PETSC(VecGetArray(coords, &c));
  for (int64_t i = 0; i < 3 * nowned; ++i) c[i] = X_local_[i];
  HS_PETSC(VecRestoreArray(coords, &c));
  MatNullSpace nullspace;
  HS_PETSC(MatNullSpaceCreateRigidBody(coords, &nullspace));
  HS_PETSC(MatSetNearNullSpace(A, nullspace));
  HS_PETSC(MatNullSpaceDestroy(&nullspace));
  HS_PETSC(VecDestroy(&coords));
  return A;
}

// The consistent mass matrix in the tangent's pattern (element blocks, unit diagonal on
// Dirichlet rows, zero elsewhere), by coordinates like the tangent.
Mat Problem::create_mass_matrix() {
  Mat M = create_matrix();
  std::vector<PetscScalar> values(tangent_values_.size(), 0.0);
  PetscScalar* value = values.data();
  const int n = 3 * npe_;
  double X[30];
  for (size_t e = 0; e < dist_.local_tets.size(); ++e, value += n * n) {
    element_coordinates(e, X);
    const auto& m = materials_[mesh_.tet_volume[dist_.local_tets[e]]];
    tet_mass(mesh_.order, X, m.density, value);
  }
  value += num_face_entries();
  for (int64_t l = 0; l < 3 * dist_.num_owned(); ++l)
    if (constrained_[l]) *value++ = 1.0;
  HS_PETSC(MatSetValuesCOO(M, values.data(), INSERT_VALUES));
  return M;
}

double Problem::prescribed_value(int64_t l, double s) const {
  if (from_exact_[l]) {
    const int64_t node = l / 3;
    const std::array<double, 3> X = {X_local_[3 * node], X_local_[3 * node + 1],
                                     X_local_[3 * node + 2]};
    return exact_(X, s)[l % 3];
  }
  return prescribed_[l] * (scaled_[l] ? s : 1.0);
}

void Problem::apply_dirichlet(Vec u, double s) const {
  PetscScalar* a;
  HS_PETSC(VecGetArray(u, &a));
  for (int64_t l = 0; l < 3 * dist_.num_owned(); ++l)
    if (constrained_[l]) a[l] = prescribed_value(l, s);
  HS_PETSC(VecRestoreArray(u, &a));
}

template <class F>
void Problem::assemble_local(Vec u, Vec out, F add) {
  LocalView view(u, u_work_);
  Vec rl;
  HS_PETSC(VecGhostGetLocalForm(r_work_, &rl));
  HS_PETSC(VecSet(rl, 0.0));
  PetscScalar* ra;
  HS_PETSC(VecGetArray(rl, &ra));
  add(view.values(), ra);
  HS_PETSC(VecRestoreArray(rl, &ra));
  HS_PETSC(VecGhostRestoreLocalForm(r_work_, &rl));
  HS_PETSC(VecGhostUpdateBegin(r_work_, ADD_VALUES, SCATTER_REVERSE));
  HS_PETSC(VecGhostUpdateEnd(r_work_, ADD_VALUES, SCATTER_REVERSE));
  HS_PETSC(VecCopy(r_work_, out));
}

// out = a f_int(u) + b (s f_body + f_pressure(u; s) + f_extra), assembled over local elements
// and faces. Returns false on an inverted element.
bool Problem::assemble_forces(Vec u, double s, double a, double b, Vec out, double* energy) {
  int64_t bad = -1;
  double local_energy = 0;
  assemble_local(u, out, [&](const PetscScalar* ua, PetscScalar* ra) {
    const int n = 3 * npe_;
    double re[30];
    for (size_t e = 0; e < dist_.local_tets.size(); ++e) {
      const int32_t* nodes = &dist_.tet_nodes[e * npe_];
      if (a != 0) {
        const ElementOutput out_e = element_force(e, ua, re, nullptr);
        local_energy += out_e.energy;
        if (!out_e.valid && bad < 0) bad = dist_.local_tets[e];
        for (int k = 0; k < n; ++k) ra[3 * nodes[k / 3] + k % 3] += a * re[k];
      }
      if (b != 0) {
        const double* fb = &body_force_[e * n];
        for (int k = 0; k < n; ++k) ra[3 * nodes[k / 3] + k % 3] += b * s * fb[k];
      }
    }
    if (b == 0) return;
    const int npf = mesh_.nodes_per_face();
    double xf[18], ff[18];
    for (const auto& surface : pressure_faces_)
      for (size_t f = 0; f < surface.faces.size() / npf; ++f) {
        const int32_t* nodes = &surface.faces[f * npf];
        for (int k = 0; k < 3 * npf; ++k)
          xf[k] = X_local_[3 * nodes[k / 3] + k % 3] + ua[3 * nodes[k / 3] + k % 3];
        face_pressure(mesh_.order, xf, pressure_at(surface, s), ff, nullptr);
        for (int k = 0; k < 3 * npf; ++k) ra[3 * nodes[k / 3] + k % 3] += b * ff[k];
      }
  });
  if (b != 0 && extra_load_) HS_PETSC(VecAXPY(out, b, extra_load_));
  if (energy) MPI_Allreduce(&local_energy, energy, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return record_inverted(bad);
}

bool Problem::record_inverted(int64_t local_bad) {
  long long bad = local_bad;
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_LONG_LONG, MPI_MAX, comm_);
  inverted_element_ = bad;
  return bad < 0;
}

int Problem::add_cavity_surface(const std::string& group) {
  if (pattern_fixed_)
    throw std::logic_error("Problem::add_cavity_surface after the tangent's matrix was created");
  PressureSurface s;
  s.value = 0;
  s.scaled = false;
  auto it = dist_.faces.find(group);
  if (it != dist_.faces.end()) s.faces = it->second;
  pressure_faces_.push_back(std::move(s));
  return static_cast<int>(pressure_faces_.size()) - 1;
}

double Problem::enclosed_volume(int surface, Vec u) {
  LocalView view(u, u_work_);
  const PetscScalar* ua = view.values();
  const int npf = mesh_.nodes_per_face();
  const auto& faces = pressure_faces_[surface].faces;
  double local = 0, xf[18];
  for (size_t f = 0; f < faces.size() / npf; ++f) {
    const int32_t* nodes = &faces[f * npf];
    for (int k = 0; k < 3 * npf; ++k)
      xf[k] = X_local_[3 * nodes[k / 3] + k % 3] + ua[3 * nodes[k / 3] + k % 3];
    local += face_enclosed_volume(mesh_.order, xf);
  }
  double total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return total;
}

void Problem::volume_gradient(int surface, Vec u, Vec g) {
  assemble_local(u, g, [&](const PetscScalar* ua, PetscScalar* ra) {
    const int npf = mesh_.nodes_per_face();
    const auto& faces = pressure_faces_[surface].faces;
    double xf[18], ff[18];
    for (size_t f = 0; f < faces.size() / npf; ++f) {
      const int32_t* nodes = &faces[f * npf];
      for (int k = 0; k < 3 * npf; ++k)
        xf[k] = X_local_[3 * nodes[k / 3] + k % 3] + ua[3 * nodes[k / 3] + k % 3];
      face_pressure(mesh_.order, xf, 1.0, ff, nullptr);
      for (int k = 0; k < 3 * npf; ++k) ra[3 * nodes[k / 3] + k % 3] += ff[k];
    }
  });
  zero_constrained(g);
}

std::array<double, 3> Problem::area_vector(const std::string& group, Vec u) {
  std::array<double, 3> local{0, 0, 0}, total{0, 0, 0};
  auto it = dist_.faces.find(group);
  if (it != dist_.faces.end()) {
    LocalView view(u, u_work_);
    const PetscScalar* ua = view.values();
    const int npf = mesh_.nodes_per_face();
    double xf[18], ff[18];
    for (size_t f = 0; f < it->second.size() / npf; ++f) {
      const int32_t* nodes = &it->second[f * npf];
      for (int k = 0; k < 3 * npf; ++k)
        xf[k] = X_local_[3 * nodes[k / 3] + k % 3] + ua[3 * nodes[k / 3] + k % 3];
      face_pressure(mesh_.order, xf, -1.0, ff, nullptr);  // f_a = int N_a n da
      for (int k = 0; k < 3 * npf; ++k) local[k % 3] += ff[k];
    }
  }
  MPI_Allreduce(local.data(), total.data(), 3, MPI_DOUBLE, MPI_SUM, comm_);
  return total;
}

void Problem::zero_constrained(Vec v) const {
  PetscScalar* a;
  HS_PETSC(VecGetArray(v, &a));
  for (int64_t l = 0; l < 3 * dist_.num_owned(); ++l)
    if (constrained_[l]) a[l] = 0;
  HS_PETSC(VecRestoreArray(v, &a));
}

bool Problem::residual(Vec u, double s, Vec R) {
  const double t0 = MPI_Wtime();
  const bool ok = assemble_forces(u, s, 1.0, -1.0, R, nullptr);
  if (inertia_) {  // + c M (u - u_pred)
    Vec du;
    HS_PETSC(VecDuplicate(u, &du));
    HS_PETSC(VecWAXPY(du, -1.0, inertia_->u_pred, u));
    HS_PETSC(VecScale(du, inertia_->c));
    HS_PETSC(MatMultAdd(inertia_->M, du, R, R));
    HS_PETSC(VecDestroy(&du));
  }
  // Dirichlet rows: R_D = u_D - g_D(s).
  PetscScalar* r;
  const PetscScalar* uo;
  HS_PETSC(VecGetArray(R, &r));
  HS_PETSC(VecGetArrayRead(u, &uo));
  for (int64_t l = 0; l < 3 * dist_.num_owned(); ++l)
    if (constrained_[l]) r[l] = uo[l] - prescribed_value(l, s);
  HS_PETSC(VecRestoreArrayRead(u, &uo));
  HS_PETSC(VecRestoreArray(R, &r));
  timers_.residual_s += MPI_Wtime() - t0;
  ++timers_.residual_calls;
  return ok;
}

bool Problem::jacobian(Vec u, double s, Mat J) {
  const double t0 = MPI_Wtime();
  int64_t bad = -1;
  // Values in the order of tangent_entries; kernels write their blocks in place.
  PetscScalar* value = tangent_values_.data();
  {
    LocalView view(u, u_work_);
    const PetscScalar* ua = view.values();
    const int n = 3 * npe_;
    double re[30];
    for (size_t e = 0; e < dist_.local_tets.size(); ++e, value += n * n) {
      const ElementOutput out = element_force(e, ua, re, value);
      if (!out.valid && bad < 0) bad = dist_.local_tets[e];
    }
    const int npf = mesh_.nodes_per_face();
    const int nf = 3 * npf;
    double xf[18], ff[18];
    for (const auto& surface : pressure_faces_) {
      for (size_t f = 0; f < surface.faces.size() / npf; ++f, value += nf * nf) {
        const int32_t* nodes = &surface.faces[f * npf];
        for (int a = 0; a < npf; ++a)
          for (int d = 0; d < 3; ++d)
            xf[3 * a + d] = X_local_[3 * nodes[a] + d] + ua[3 * nodes[a] + d];
        face_pressure(mesh_.order, xf, pressure_at(surface, s), ff, value);
        for (int k = 0; k < nf * nf; ++k) value[k] = -value[k];  // R = ... - f_pressure
      }
    }
  }
  fill_constraint_entries(value);
  HS_PETSC(MatSetValuesCOO(J, tangent_values_.data(), INSERT_VALUES));
  if (inertia_) HS_PETSC(MatAXPY(J, inertia_->c, inertia_->M, SUBSET_NONZERO_PATTERN));

  const bool ok = record_inverted(bad);
  timers_.jacobian_s += MPI_Wtime() - t0;
  ++timers_.jacobian_calls;
  return ok;
}

void Problem::internal_force(Vec u, Vec f, double* energy) {
  assemble_forces(u, 0.0, 1.0, 0.0, f, energy);
}

void Problem::external_load(Vec u, double s, Vec f) { assemble_forces(u, s, 0.0, 1.0, f, nullptr); }

void Problem::element_fields(Vec u, std::vector<double>& von_mises, std::vector<double>& J) const {
  Vec uw;
  HS_PETSC(VecDuplicate(u_work_, &uw));
  {
    LocalView view(u, uw);
    const PetscScalar* ua = view.values();
    const auto nt = dist_.local_tets.size();
    von_mises.resize(nt);
    J.resize(nt);
    double X[30], ue[30];
    for (size_t e = 0; e < nt; ++e) {
      element_coordinates(e, X);
      element_displacement(ua, e, ue);
      const auto& m = materials_[mesh_.tet_volume[dist_.local_tets[e]]];
      const ElementFields f = tet_fields(mesh_.order, X, ue, *m.law);
      von_mises[e] = f.von_mises;
      J[e] = f.J;
    }
  }
  HS_PETSC(VecDestroy(&uw));
}

bool Problem::orientation_preserved(Vec u) const {
  Vec uw;
  HS_PETSC(VecDuplicate(u_work_, &uw));
  int ok = 1;
  {
    LocalView view(u, uw);
    const PetscScalar* ua = view.values();
    double X[30], ue[30];
    for (size_t e = 0; e < dist_.local_tets.size() && ok; ++e) {
      element_coordinates(e, X);
      element_displacement(ua, e, ue);
      ok = tet_orientation_preserved(mesh_.order, X, ue);
    }
  }
  HS_PETSC(VecDestroy(&uw));
  int all = 0;
  MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, comm_);
  return all;
}

std::vector<double> Problem::gather_nodal(Vec v) const {
  const int nowned = static_cast<int>(dist_.num_owned());
  const PetscScalar* a;
  HS_PETSC(VecGetArrayRead(v, &a));
  std::vector<double> mine(a, a + 3 * nowned);
  HS_PETSC(VecRestoreArrayRead(v, &a));
  std::vector<double> all;
  std::vector<int> counts(dist_.size), displs(dist_.size);
  for (int r = 0; r < dist_.size; ++r) {
    counts[r] = static_cast<int>(3 * (dist_.owned_offsets[r + 1] - dist_.owned_offsets[r]));
    displs[r] = static_cast<int>(3 * dist_.owned_offsets[r]);
  }
  if (dist_.rank == 0) all.resize(3 * dist_.num_global());
  MPI_Gatherv(mine.data(), 3 * nowned, MPI_DOUBLE, all.data(), counts.data(), displs.data(),
              MPI_DOUBLE, 0, comm_);
  if (dist_.rank != 0) return {};
  // New (rank-contiguous) numbering to mesh numbering.
  std::vector<double> out(all.size());
  for (int64_t old = 0; old < mesh_.num_nodes(); ++old)
    for (int d = 0; d < 3; ++d) out[3 * old + d] = all[3 * dist_.new_of_old[old] + d];
  return out;
}

std::vector<double> Problem::gather_elemental(const std::vector<double>& local) const {
  const int n = static_cast<int>(local.size());
  std::vector<int> counts(dist_.size), displs(dist_.size);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_);
  std::vector<long long> ids(dist_.local_tets.begin(), dist_.local_tets.end());
  int total = 0;
  if (dist_.rank == 0)
    for (int r = 0; r < dist_.size; ++r) {
      displs[r] = total;
      total += counts[r];
    }
  std::vector<double> values(total);
  std::vector<long long> all_ids(total);
  MPI_Gatherv(local.data(), n, MPI_DOUBLE, values.data(), counts.data(), displs.data(), MPI_DOUBLE,
              0, comm_);
  MPI_Gatherv(ids.data(), n, MPI_LONG_LONG, all_ids.data(), counts.data(), displs.data(),
              MPI_LONG_LONG, 0, comm_);
  if (dist_.rank != 0) return {};
  std::vector<double> out(mesh_.num_tets(), 0.0);
  for (int i = 0; i < total; ++i) out[all_ids[i]] = values[i];
  return out;
}

double Problem::total_mass() const {
  double local = 0, X[30];
  for (size_t e = 0; e < dist_.local_tets.size(); ++e) {
    element_coordinates(e, X);
    local += materials_[mesh_.tet_volume[dist_.local_tets[e]]].density * tet_volume(mesh_.order, X);
  }
  double total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return total;
}

}  // namespace hs
