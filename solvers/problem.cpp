#include "solvers/problem.hpp"

#include <petscsys.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "common/error.hpp"
#include "fem/element.hpp"
#include "materials/elastic_constants.hpp"
#include "materials/volumetric_term.hpp"
#include "solvers/mixed_factor.hpp"

namespace hs {

Problem::Problem(const Config& config, const Distribution& dist, MPI_Comm comm,
                 ExactDirichlet exact, const ForceDensity& body_force)
    : comm_(comm),
      dist_(dist),
      npe_(dist.nodes_per_tet()),
      dofs_(config, dist, std::move(exact)),
      X_(dofs_.reference()) {
  // Materials per volume group of the mesh.
  const std::vector<std::string>& volumes = dist.groups.volumes;
  materials_.resize(volumes.size());
  std::vector<char> has_material(volumes.size(), 0);
  for (const auto& mc : config.materials) {
    auto it = std::find(volumes.begin(), volumes.end(), mc.group);
    if (it == volumes.end()) throw InputError("material group '" + mc.group + "' is not a volume");
    const auto v = static_cast<size_t>(it - volumes.begin());
    materials_[v] = mc;
    has_material[v] = 1;
  }
  for (size_t v = 0; v < has_material.size(); ++v)
    if (!has_material[v]) throw InputError("volume group '" + volumes[v] + "' has no material");

  // Body force per local tet at full load.
  const auto nt = dist.local_tets.size();
  body_force_.assign(nt * 3 * npe_, 0.0);
  std::vector<double> X(3 * npe_);
  for (size_t e = 0; e < nt; ++e) {
    element_coordinates(e, X.data());
    const auto& m = materials_[dist.tet_volume[e]];
    double* f = &body_force_[e * 3 * npe_];
    tet_body_force(dist.order, X.data(), m.density, config.gravity, f);
    if (body_force) {
      std::vector<double> field(3 * npe_);
      tet_body_force(dist.order, X.data(), body_force, field.data());
      for (int k = 0; k < 3 * npe_; ++k) f[k] += field[k];
    }
    if (dist.order == 1) p1_geometry_.push_back(tet_p1_geometry(X.data()));
  }
  bool any_nodal = false, any_fbar_term = false;
  for (const auto& m : materials_) {
    const bool nodal = m.element == ElementFormulation::nodal_pressure;
    if (nodal && dist.order != 1)
      throw InputError("material group '" + m.group + "': nodal_pressure needs a P1 mesh");
    element_laws_.push_back(nodal ? std::make_shared<WithoutVolumetricTerm>(m.law) : m.law);
    any_nodal |= nodal;
    const bool split = m.element == ElementFormulation::fbar && !m.law->small_strain() &&
                       m.law->has_volumetric_term();
    fbar_rest_laws_.push_back(split ? std::make_shared<WithoutVolumetricTerm>(m.law) : nullptr);
    fbar_modulus_.push_back(split ? fbar_rest_laws_.back()->removed_modulus() : 0.0);
    any_fbar_term |= split;
  }
  if (any_fbar_term) fbar_linearization_.resize(nt);
  for (const auto& m : materials_)  // the same on every rank: the deck's materials
    has_fbar_multipliers_ |=
        m.element == ElementFormulation::fbar && hs::incompressible(m.law->elastic_constants());
  has_volume_multipliers_ = has_fbar_multipliers_;
  if (has_volume_multipliers_) {  // exactly incompressible F-bar elements
    fbar_incompressible_.assign(nt, 0);
    fbar_lambda_.assign(nt, 0.0);
    fbar_ln_Jbar_.assign(nt, 0.0);
    for (size_t e = 0; e < nt; ++e)
      fbar_incompressible_[e] =
          materials_[dist.tet_volume[e]].element == ElementFormulation::fbar &&
          hs::incompressible(materials_[dist.tet_volume[e]].law->elastic_constants());
  }
  if (any_nodal) {          // every rank: the materials are the deck's
    int small_strain = -1;  // of the nodal-pressure materials: one kind of volume change
    for (const auto& m : materials_) {
      if (m.element != ElementFormulation::nodal_pressure) continue;
      if (small_strain >= 0 && small_strain != m.law->small_strain())
        throw InputError("material group '" + m.group +
                         "': nodal_pressure bodies of small-strain and finite-strain laws "
                         "cannot share nodes; give one of them formulation: displacement");
      small_strain = m.law->small_strain();
    }
    std::vector<double> modulus(nt, -1.0);
    std::vector<char> incompressible(nt, 0);
    for (size_t e = 0; e < nt; ++e) {
      const auto& m = materials_[dist.tet_volume[e]];
      if (m.element != ElementFormulation::nodal_pressure) continue;
      modulus[e] = m.law->volumetric_modulus();
      incompressible[e] = hs::incompressible(m.law->elastic_constants());
    }
    nodal_ = std::make_unique<NodalPressure>(dist, p1_geometry_, std::move(modulus), incompressible,
                                             small_strain == 1, dofs_, comm);
    has_volume_multipliers_ |= nodal_->has_multipliers();
  }

  for (const auto& pc : config.pressures) {
    auto it = dist.faces.find(pc.group);
    PressureSurface s;
    s.value = pc.value;
    if (it != dist.faces.end()) s.faces = it->second;
    pressure_faces_.push_back(std::move(s));
  }
  const int npf = dist.nodes_per_face();
  for (const auto& tc : config.tractions) {
    auto it = dist.faces.find(tc.group);
    if (it == dist.faces.end()) continue;
    double Xf[18], ff[18];
    for (size_t f = 0; f < it->second.size() / npf; ++f) {
      const int32_t* nodes = &it->second[f * npf];
      for (int k = 0; k < 3 * npf; ++k) Xf[k] = X_[3 * nodes[k / 3] + k % 3];
      face_traction(dist.order, Xf, tc.value, ff);
      traction_faces_.insert(traction_faces_.end(), nodes, nodes + npf);
      traction_forces_.insert(traction_forces_.end(), ff, ff + 3 * npf);
    }
  }
  bool any_faces = false;
  for (const auto& s : pressure_faces_) any_faces |= !s.faces.empty();
  int local_any = any_faces, global_any = 0;
  MPI_Allreduce(&local_any, &global_any, 1, MPI_INT, MPI_MAX, comm_);
  if (!global_any) pressure_faces_.clear();

  u_work_ = VecHandle(create_vector());
  HS_PETSC(VecDuplicate(u_work_, r_work_.out()));
  contact_surfaces_ = config.contact.surfaces;
  if (!config.obstacles.empty())
    contact_ = std::make_unique<ObstacleContact>(config, dist, X_, u_work_, comm_);
  if (config.contact.self) {
    std::vector<char> fixed(dofs_.num_owned_dofs());
    for (int64_t l = 0; l < dofs_.num_owned_dofs(); ++l) fixed[l] = dofs_.constrained(l);
    self_contact_ =
        std::make_unique<SelfContact>(config, dist, fixed, contact_barrier_of(config, X_, comm_),
                                      config.solver.preset == SolverPreset::gamg, comm_);
  }
}

Problem::~Problem() = default;

void Problem::element_coordinates(int64_t e, double* X) const {
  const int32_t* nodes = &dist_.tet_nodes[e * npe_];
  for (int a = 0; a < npe_; ++a)
    for (int d = 0; d < 3; ++d) X[3 * a + d] = X_[3 * nodes[a] + d];
}

ElementOutput Problem::element_force(int64_t e, const PetscScalar* ua, double* r, double* K,
                                     bool patch_share) const {
  double X[30], ue[30];
  element_displacement(ua, e, ue);
  const auto& m = materials_[dist_.tet_volume[e]];
  const MaterialLaw& law = *element_laws_[dist_.tet_volume[e]];
  if (!p1_geometry_.empty()) {
    const ElementOutput out = tet_internal_force_p1(p1_geometry_[e], ue, law, r, K);
    if (patch_share && nodal_ && nodal_->takes_part(e)) nodal_->add_element(e, ue, r, K);
    return out;
  }
  element_coordinates(e, X);
  if (fbar_incompressible(e)) {  // the law split, its term with the element's volume multiplier
    FbarNewtonPressure p = fbar_pressure(e);
    return tet_internal_force_fbar(dist_.order, X, ue, p, r, K);
  }
  if (m.element == ElementFormulation::fbar)
    return tet_internal_force_fbar(dist_.order, X, ue, law, r, K);
  return tet_internal_force(dist_.order, X, ue, law, r, K);
}

ElementOutput Problem::element_tangent(int64_t e, const PetscScalar* ua, double* r, double* K) {
  const WithoutVolumetricTerm* rest =
      fbar_linearization_.empty() ? nullptr : fbar_rest_laws_[dist_.tet_volume[e]].get();
  if (!rest) return element_force(e, ua, r, K);
  const int n = 3 * npe_;
  double X[30], ue[30];
  element_coordinates(e, X);
  element_displacement(ua, e, ue);
  FbarLinearization& lin = fbar_linearization_[e];
  FbarNewtonPressure p = fbar_pressure(e);
  p.exact = !lin.valid;
  if (lin.valid) {
    double g_u = 0;
    for (int k = 0; k < n; ++k) g_u += lin.g[k] * ue[k];
    p.q = p.k * (lin.c0 + g_u);
  }
  const ElementOutput out = tet_internal_force_fbar(dist_.order, X, ue, p, r, K);
  lin.valid = out.valid;
  if (out.valid) {
    lin.c0 = p.ln_Jbar;
    for (int k = 0; k < n; ++k) {
      lin.g[k] = p.g[k];
      lin.c0 -= p.g[k] * ue[k];
    }
  }
  return out;
}

FbarNewtonPressure Problem::fbar_pressure(int64_t e) const {
  const int v = dist_.tet_volume[e];
  FbarNewtonPressure p;
  p.rest = fbar_rest_laws_[v].get();
  p.k = fbar_modulus_[v];
  p.lambda = fbar_lambda_.empty() ? 0.0 : fbar_lambda_[e];
  return p;
}

void Problem::element_displacement(const PetscScalar* u_local, int64_t e, double* u) const {
  const int32_t* nodes = &dist_.tet_nodes[e * npe_];
  for (int a = 0; a < npe_; ++a)
    for (int d = 0; d < 3; ++d) u[3 * a + d] = u_local[3 * nodes[a] + d];
}

// out = a f_int(u) + b (s f_body + f_pressure(u; s) + f_extra), assembled over local elements
// and faces. Returns false on an inverted element.
bool Problem::assemble_forces(Vec u, double s, double a, double b, Vec out, double* energy) {
  int64_t bad = -1;
  int reached = -1;
  double local_energy = 0;
  assemble_local(u, out, [&](const PetscScalar* ua, PetscScalar* ra) {
    const int n = 3 * npe_;
    double re[30];
    if (a != 0 && nodal_) {
      int64_t at = -1;
      if (!nodal_->update(ua, &at) && at >= 0) bad = dist_.local_tets[at];
      local_energy += nodal_->owned_energy();
    }
    if (a != 0 && contact_) {  // the barrier's energy is stored energy: its force is a * dE/du
      const AddSeconds timed(timers_.contact_s);
      double e = 0;
      contact_->add_forces(ua, s, a, ra, &e);
      local_energy += e;
      reached = contact_->inside();
    }
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
    const int npf = dist_.nodes_per_face();
    for (size_t k = 0; k < traction_forces_.size(); ++k)
      ra[3 * traction_faces_[k / 3] + k % 3] += b * s * traction_forces_[k];
    double xf[18], ff[18];
    for (const auto& surface : pressure_faces_)
      for (size_t f = 0; f < surface.faces.size() / npf; ++f) {
        const int32_t* nodes = &surface.faces[f * npf];
        for (int k = 0; k < 3 * npf; ++k)
          xf[k] = X_[3 * nodes[k / 3] + k % 3] + ua[3 * nodes[k / 3] + k % 3];
        face_pressure(dist_.order, xf, pressure_at(surface, s), ff, nullptr);
        for (int k = 0; k < 3 * npf; ++k) ra[3 * nodes[k / 3] + k % 3] += b * ff[k];
      }
  });
  if (b != 0 && extra_load_) HS_PETSC(VecAXPY(out, b, extra_load_));
  if (a != 0 && self_contact_) {  // the pairs' barriers are stored energy too
    const AddSeconds timed(timers_.contact_s);
    LocalView view(u, u_work_);
    PetscScalar* f;
    HS_PETSC(VecGetArray(out, &f));
    double e = 0;
    self_touch_ = !self_contact_->add_forces(view.values(), a, f, &e);
    HS_PETSC(VecRestoreArray(out, &f));
    local_energy += e;
  }
  if (energy) MPI_Allreduce(&local_energy, energy, 1, MPI_DOUBLE, MPI_SUM, comm_);
  if (a != 0 && contact_) {
    MPI_Allreduce(MPI_IN_PLACE, &reached, 1, MPI_INT, MPI_MAX, comm_);
    obstacle_reached_ = reached;
  }
  const bool oriented = record_inverted(bad);
  return oriented && (a == 0 || (obstacle_reached_ < 0 && !self_touch_));
}

bool Problem::record_inverted(int64_t local_bad) {
  long long bad = local_bad;
  MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPI_LONG_LONG, MPI_MAX, comm_);
  inverted_element_ = bad;
  return bad < 0;
}

bool Problem::residual(Vec u, double s, Vec R) {
  const double t0 = MPI_Wtime();
  const bool ok = assemble_forces(u, s, 1.0, -1.0, R, nullptr);
  if (inertia_) {  // + c M (u - u_pred)
    VecHandle du;
    HS_PETSC(VecDuplicate(u, du.out()));
    HS_PETSC(VecWAXPY(du, -1.0, inertia_->u_pred, u));
    HS_PETSC(VecScale(du, inertia_->c));
    HS_PETSC(MatMultAdd(inertia_->M, du, R, R));
  }
  dofs_.set_rows(u, s, R);  // Dirichlet rows: R_D = u_D - g_D(s)
  timers_.residual_s += MPI_Wtime() - t0;
  ++timers_.residual_calls;
  return ok;
}

bool Problem::jacobian(Vec u, double s, Mat J) {
  const double t0 = MPI_Wtime();
  int64_t bad = -1;
  std::vector<SelfContact::Pair> self_pairs;
  if (self_contact_) {
    const AddSeconds timed(timers_.contact_s);
    LocalView view(u, u_work_);
    self_contact_->pairs(view.values(), self_pairs);
    if (self_contact_->extend_pattern(self_pairs)) {
      ++pattern_version_;
      std::vector<PetscInt> rows, cols;
      pattern_entries(rows, cols);
    }
  }
  update_pattern(J);
  // Values in the order of tangent_entries: element and face matrices summed into the
  // node-pair blocks, then the constraint entries.
  PetscScalar* value = tangent_values_.data();
  const int64_t block_values = 9 * pairs_->num_pairs();
  std::fill(value, value + block_values, 0.0);
  {
    LocalView view(u, u_work_);
    const PetscScalar* ua = view.values();
    int64_t at = -1;
    if (nodal_ && !nodal_->update(ua, &at) && at >= 0) bad = dist_.local_tets[at];
    if (nodal_) nodal_->linearize(ua);
    double re[30], K[900];
    for (size_t e = 0; e < dist_.local_tets.size(); ++e) {
      const ElementOutput out = element_tangent(e, ua, re, K);
      if (!out.valid && bad < 0) bad = dist_.local_tets[e];
      pairs_->add_tet(static_cast<int64_t>(e), K, value);
    }
    if (contact_) {
      const AddSeconds timed(timers_.contact_s);
      contact_->add_tangent(ua, s, *pairs_, value);
    }
    const int npf = dist_.nodes_per_face();
    const int nf = 3 * npf;
    double xf[18], ff[18], Kf[324];
    for (const auto& surface : pressure_faces_) {
      for (size_t f = 0; f < surface.faces.size() / npf; ++f) {
        const int32_t* nodes = &surface.faces[f * npf];
        for (int a = 0; a < npf; ++a)
          for (int d = 0; d < 3; ++d) xf[3 * a + d] = X_[3 * nodes[a] + d] + ua[3 * nodes[a] + d];
        face_pressure(dist_.order, xf, pressure_at(surface, s), ff, Kf);
        for (int k = 0; k < nf * nf; ++k) Kf[k] = -Kf[k];  // R = ... - f_pressure
        pairs_->add_nodes(nodes, npf, Kf, value);
      }
    }
    if (nodal_)
      nodal_->fill_coupling(
          ua, tangent_values_.data() + tangent_values_.size() - nodal_->num_coupling_entries());
  }
  fill_constraint_entries(value + block_values);
  if (self_contact_) {
    const AddSeconds timed(timers_.contact_s);
    const size_t nodal = nodal_ ? nodal_->num_coupling_entries() : 0;
    self_contact_->fill_tangent(self_pairs, tangent_values_.data() + tangent_values_.size() -
                                                nodal - 9 * self_contact_->pattern().size());
  }
  HS_PETSC(MatSetValuesCOO(J, tangent_values_.data(), INSERT_VALUES));
  if (inertia_) HS_PETSC(MatAXPY(J, inertia_->c, inertia_->M, SUBSET_NONZERO_PATTERN));
  PetscObject mixed = nullptr;
  if (nodal_)
    HS_PETSC(PetscObjectQuery(reinterpret_cast<PetscObject>(J), kMixedTangentKey, &mixed));
  if (mixed) fill_mixed_matrix(reinterpret_cast<Mat>(mixed));

  const bool ok = record_inverted(bad);
  timers_.jacobian_s += MPI_Wtime() - t0;
  ++timers_.jacobian_calls;
  return ok;
}

void Problem::exact_next_tangent() {
  if (nodal_) nodal_->forget_linearization();
  for (FbarLinearization& lin : fbar_linearization_) lin.valid = false;
}

Problem::TangentMemory Problem::tangent_memory() const {
  TangentMemory memory;
  if (nodal_) memory.nodal = nodal_->linearization();
  memory.fbar = fbar_linearization_;
  return memory;
}

void Problem::restore_tangent_memory(TangentMemory memory) {
  if (nodal_) nodal_->set_linearization(std::move(memory.nodal));
  fbar_linearization_ = std::move(memory.fbar);
}

void Problem::internal_force(Vec u, Vec f, double* energy) {
  assemble_forces(u, 0.0, 1.0, 0.0, f, energy);
}

bool Problem::potential_energy(Vec u, double s, double* energy) {
  if (!has_potential_at_held_pressures())
    throw std::logic_error("potential_energy: the loads have no potential");
  const double t0 = MPI_Wtime();
  VecHandle f;
  HS_PETSC(VecDuplicate(u, f.out()));
  double stored = 0;
  // The forces are not used; s places moving obstacles (b = 0: no load is added).
  const bool ok = assemble_forces(u, s, 1.0, 0.0, f, &stored);
  PetscScalar work = 0;
  if (ok) {
    assemble_forces(u, s, 0.0, 1.0, f, nullptr);  // s f_body, and the cavities' pressures
    if (has_cavity_surfaces()) {
      VecHandle pressure;
      HS_PETSC(VecDuplicate(u, pressure.out()));
      cavity_pressure_load(u, pressure);
      HS_PETSC(VecAXPY(f, -1.0, pressure));
      for (size_t k = 0; k < pressure_faces_.size(); ++k)
        if (!pressure_faces_[k].scaled)
          work += pressure_faces_[k].value * enclosed_volume(static_cast<int>(k), u);
    }
    PetscScalar body = 0;
    HS_PETSC(VecDot(f, u, &body));
    work += body;
  }
  double kinetic = 0;
  if (ok && inertia_) {
    VecHandle du;
    HS_PETSC(VecWAXPY(f, -1.0, inertia_->u_pred, u));
    HS_PETSC(VecDuplicate(u, du.out()));
    HS_PETSC(MatMult(inertia_->M, f, du));
    PetscScalar dMd = 0;
    HS_PETSC(VecDot(f, du, &dMd));
    kinetic = 0.5 * inertia_->c * dMd;
  }
  timers_.residual_s += MPI_Wtime() - t0;
  if (ok) *energy = stored - work + kinetic;
  return ok;
}

double Problem::residual_roundoff(Vec u) {
  VecHandle bound;
  HS_PETSC(VecDuplicate(u, bound.out()));
  assemble_local(u, bound, [&](const PetscScalar* ua, PetscScalar* ra) {
    const int n = 3 * npe_;
    double X[30], ue[30], re[30], K[900], size[30];
    for (size_t e = 0; e < dist_.local_tets.size(); ++e) {
      element_force(static_cast<int64_t>(e), ua, re, K);
      element_coordinates(static_cast<int64_t>(e), X);
      element_displacement(ua, static_cast<int64_t>(e), ue);
      if (nodal_ && nodal_->takes_part(e)) nodal_->add_element_scale(e, ue, K);
      double c[3] = {0, 0, 0};
      for (int k = 0; k < n; ++k) c[k % 3] += X[k] / npe_;
      for (int k = 0; k < n; ++k) size[k] = std::abs(ue[k]) + std::abs(X[k] - c[k % 3]);
      const int32_t* nodes = &dist_.tet_nodes[e * npe_];
      for (int i = 0; i < n; ++i) {
        double sum = 0;
        for (int j = 0; j < n; ++j) sum += std::abs(K[i * n + j]) * size[j];
        ra[3 * nodes[i / 3] + i % 3] += sum;
      }
    }
  });
  if (self_contact_) {
    LocalView view(u, u_work_);
    PetscScalar* b;
    HS_PETSC(VecGetArray(bound, &b));
    self_contact_->add_roundoff(view.values(), b);
    HS_PETSC(VecRestoreArray(bound, &b));
  }
  dofs_.zero(bound);
  PetscReal norm = 0;
  HS_PETSC(VecNorm(bound, NORM_2, &norm));
  return std::numeric_limits<double>::epsilon() * norm;
}

void Problem::external_load(Vec u, double s, Vec f) { assemble_forces(u, s, 0.0, 1.0, f, nullptr); }

void Problem::element_fields(Vec u, ElementFieldValues& v, bool principal) const {
  VecHandle uw;
  HS_PETSC(VecDuplicate(u_work_, uw.out()));
  LocalView view(u, uw);
  const PetscScalar* ua = view.values();
  const auto nt = dist_.local_tets.size();
  v.von_mises.resize(nt);
  v.J.resize(nt);
  v.stress.resize(9 * nt);
  v.strain.resize(9 * nt);
  v.principal_stress.resize(principal ? 3 * nt : 0);
  v.principal_strain.resize(principal ? 3 * nt : 0);
  if (nodal_) nodal_->update(ua, nullptr);
  double X[30], ue[30];
  for (size_t e = 0; e < nt; ++e) {
    element_coordinates(e, X);
    element_displacement(ua, e, ue);
    const auto& m = materials_[dist_.tet_volume[e]];
    const MaterialLaw& law = *element_laws_[dist_.tet_volume[e]];
    const bool split = fbar_incompressible(e);  // the rest law and the term's own stress
    ElementFields f = m.element == ElementFormulation::fbar
                          ? tet_fields_fbar(dist_.order, X, ue,
                                            split ? *fbar_rest_laws_[dist_.tet_volume[e]] : law)
                          : tet_fields(dist_.order, X, ue, law);
    if (nodal_ && nodal_->takes_part(e))  // the volumetric stress of the element's nodes
      f.stress += nodal_->element_pressure(e) * Mat3::Identity();
    if (split) {  // V (lambda ln Jbar + k/2 (ln Jbar)^2): the Cauchy stress (lambda + k ln Jbar) /
                  // Jbar
      const FbarNewtonPressure p = fbar_pressure(e);
      f.stress += (p.lambda + p.k * std::log(f.J)) / f.J * Mat3::Identity();
    }
    v.von_mises[e] = f.von_mises;
    v.J[e] = f.J;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        v.stress[9 * e + 3 * i + j] = f.stress(i, j);
        v.strain[9 * e + 3 * i + j] = f.strain(i, j);
      }
    if (!principal) continue;
    const auto ps = principal_values(f.stress), pe = principal_values(f.strain);
    std::copy(ps.begin(), ps.end(), &v.principal_stress[3 * e]);
    std::copy(pe.begin(), pe.end(), &v.principal_strain[3 * e]);
  }
}

std::vector<double> Problem::nodal_pressure(Vec u) const {
  if (!nodal_) return {};
  VecHandle uw;
  HS_PETSC(VecDuplicate(u_work_, uw.out()));
  LocalView view(u, uw);
  nodal_->update(view.values(), nullptr);
  return nodal_->owned_compression();
}

std::vector<std::array<double, 3>> Problem::reactions(Vec u, double s) {
  VecHandle r;
  HS_PETSC(VecDuplicate(u, r.out()));
  assemble_forces(u, s, 1.0, -1.0, r, nullptr);  // f_int - f_ext, owned entries complete
  const int n = static_cast<int>(dofs_.groups().size());
  std::vector<double> sums(3 * n, 0.0);
  const PetscScalar* a;
  HS_PETSC(VecGetArrayRead(r, &a));
  for (int64_t l = 0; l < dofs_.num_owned_dofs(); ++l)
    if (dofs_.constrained(l)) sums[3 * dofs_.group_of(l) + l % 3] += a[l];
  HS_PETSC(VecRestoreArrayRead(r, &a));
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), 3 * n, MPI_DOUBLE, MPI_SUM, comm_);
  std::vector<std::array<double, 3>> out(n);
  for (int g = 0; g < n; ++g) out[g] = {sums[3 * g], sums[3 * g + 1], sums[3 * g + 2]};
  return out;
}

bool Problem::orientation_preserved(Vec u) {
  VecHandle uw;
  HS_PETSC(VecDuplicate(u_work_, uw.out()));
  int64_t bad = -1;
  {
    LocalView view(u, uw);
    const PetscScalar* ua = view.values();
    double X[30], ue[30];
    for (size_t e = 0; e < dist_.local_tets.size() && bad < 0; ++e) {
      element_coordinates(e, X);
      element_displacement(ua, e, ue);
      if (!tet_orientation_preserved(dist_.order, X, ue)) bad = dist_.local_tets[e];
    }
  }
  return record_inverted(bad);
}

}  // namespace hs
