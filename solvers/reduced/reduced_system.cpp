#include "solvers/reduced/reduced_system.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "common/error.hpp"
#include "solvers/reduced/model_fit.hpp"

namespace hs {
namespace {

// Newton's test: |r| at most this fraction of the forces it balances.
constexpr double kRelativeTolerance = 1e-10;
constexpr int kMaxIterations = 25;

// The local dofs where v is not zero.
void add_support(Vec v, std::set<PetscInt>& dofs) {
  PetscInt n = 0;
  HS_PETSC(VecGetLocalSize(v, &n));
  const PetscScalar* a = nullptr;
  HS_PETSC(VecGetArrayRead(v, &a));
  for (PetscInt i = 0; i < n; ++i)
    if (a[i] != 0) dofs.insert(i);
  HS_PETSC(VecRestoreArrayRead(v, &a));
}

}  // namespace

Eigen::VectorXd local_values(Vec v) {
  PetscInt n = 0;
  HS_PETSC(VecGetLocalSize(v, &n));
  const PetscScalar* a = nullptr;
  HS_PETSC(VecGetArrayRead(v, &a));
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(a, n);
  HS_PETSC(VecRestoreArrayRead(v, &a));
  return x;
}

ReducedSystem::ReducedSystem(const Config& config, Problem& problem, ConstraintSet& constraints,
                             const ReducedModel& model, const std::string& path,
                             const std::vector<Vec>& rows)
    : problem_(problem), constraints_(constraints) {
  check_model_fits(config, problem, constraints, model, path);
  const Distribution& dist = problem.distribution();
  const int k = static_cast<int>(model.basis.cols());
  const int64_t nodes = dist.num_local();
  phi_.resize(3 * nodes, k);
  for (int64_t n = 0; n < nodes; ++n)
    phi_.middleRows(3 * n, 3) = model.basis.middleRows(3 * dist.old_of_local[n], 3);
  // Each sampled tetrahedron by its local index (local_tets is ascending).
  for (size_t i = 0; i < model.elements.size(); ++i) {
    const auto it =
        std::lower_bound(dist.local_tets.begin(), dist.local_tets.end(), model.elements[i]);
    elements_.push_back(it - dist.local_tets.begin());
    weights_.push_back(model.weights[i]);
  }
  const int npe = dist.nodes_per_tet();
  std::set<PetscInt> dofs;
  for (int64_t e : elements_) {
    Eigen::MatrixXd rows_e(3 * npe, k);
    for (int a = 0; a < npe; ++a) {
      const int32_t node = dist.tet_nodes[e * npe + a];
      rows_e.middleRows(3 * a, 3) = phi_.middleRows(3 * node, 3);
      for (int d = 0; d < 3; ++d) dofs.insert(3 * node + d);
    }
    phi_element_.push_back(rows_e);
  }
  nodal_ = problem.nodal_pressure();
  if (!model.patches.empty()) {
    if (!nodal_)
      throw InputError(path +
                       ": the model samples node patches, and this run's body has no "
                       "nodal-pressure element");
    std::vector<int32_t> local_of(model.nodes, -1);  // one rank: every node is local
    for (int64_t n = 0; n < nodes; ++n) local_of[dist.old_of_local[n]] = static_cast<int32_t>(n);
    const std::vector<std::vector<int64_t>> around = nodal_->patch_elements();
    for (size_t i = 0; i < model.patches.size(); ++i) {
      SampledPatch patch{local_of[model.patches[i]], model.patch_weights[i], {}, {}, {}};
      patch.elements = around[patch.node];
      if (patch.elements.empty())
        throw InputError(path + ": node " + std::to_string(model.patches[i]) +
                         " has no nodal-pressure patch in this run");
      std::vector<int32_t> nodes;
      for (int64_t e : patch.elements)
        for (int a = 0; a < 4; ++a) {
          const int32_t node = dist.tet_nodes[e * 4 + a];
          const auto at = std::find(nodes.begin(), nodes.end(), node);
          patch.slots.push_back(static_cast<int>(at - nodes.begin()));
          if (at == nodes.end()) nodes.push_back(node);
        }
      patch.phi.resize(3 * static_cast<Eigen::Index>(nodes.size()), k);
      for (size_t j = 0; j < nodes.size(); ++j) {
        patch.phi.middleRows(3 * static_cast<Eigen::Index>(j), 3) =
            phi_.middleRows(3 * nodes[j], 3);
        for (int d = 0; d < 3; ++d) dofs.insert(3 * nodes[j] + d);
      }
      patches_.push_back(std::move(patch));
    }
  }
  contact_ = problem.contact();
  if (contact_)
    for (int32_t node : contact_->nodes()) {
      phi_contact_.push_back(phi_.middleRows(3 * node, 3));
      for (int d = 0; d < 3; ++d) dofs.insert(3 * node + d);
    }
  // The constraints' support: where their forces and loads act at rest, whole nodes.
  work_ = VecHandle(problem.create_vector());
  VecHandle u(problem.create_vector()), f(problem.create_vector());
  std::set<PetscInt> touched;
  if (!constraints.loads(u, 1.0, f))
    throw InputError(path + ": the constraints have no forces on the undeformed body");
  add_support(f, touched);
  // The dead loads: external_load less the constraints' forces (at the same u, so the
  // cavities' pressures and the liquid's weight cancel exactly).
  VecHandle all(problem.create_vector());
  problem.external_load(u, 1.0, all);
  HS_PETSC(VecAXPY(all, -1.0, f));
  dead_ = project(all);
  for (int c = 0; c < constraints.size(); ++c) {
    constraints[c].forces(u, f);
    add_support(f, touched);
    HS_PETSC(VecZeroEntries(f));
    constraints[c].mark_reads(f);
    add_support(f, touched);
  }
  for (Vec row : rows) add_support(row, touched);
  for (PetscInt dof : touched)
    for (int d = 0; d < 3; ++d) dofs.insert(3 * (dof / 3) + d);
  sample_.assign(dofs.begin(), dofs.end());
  phi_sample_.resize(sample_.size(), k);
  for (size_t i = 0; i < sample_.size(); ++i) phi_sample_.row(i) = phi_.row(sample_[i]);
  for (const std::string& name : model.actuators) actuators_.push_back(constraints.find(name));
  training_actuations_ = model.training_actuations;
  training_states_ = model.training_states;
  training_range_.resize(model.lower.size());
  for (size_t a = 0; a < model.lower.size(); ++a)
    training_range_(a) = std::max(model.upper[a] - model.lower[a], 1e-300);
}

Eigen::Index ReducedSystem::nearest_training_sample(const Eigen::VectorXd& lambda) const {
  Eigen::Index best = 0;
  double best_d2 = HUGE_VAL;
  for (Eigen::Index s = 0; s < training_actuations_.rows(); ++s) {
    const double d2 =
        ((training_actuations_.row(s).transpose() - lambda).array() / training_range_.array())
            .square()
            .sum();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = s;
    }
  }
  return best;
}

double ReducedSystem::residual_norm(const Eigen::VectorXd& q, Vec u) {
  Eigen::VectorXd r;
  return residual(q, u, r, nullptr) ? r.norm() : HUGE_VAL;
}

Eigen::VectorXd ReducedSystem::project(Vec u) const {
  const PetscScalar* a = nullptr;
  HS_PETSC(VecGetArrayRead(u, &a));
  const Eigen::Map<const Eigen::VectorXd> v(a, phi_.rows());
  Eigen::VectorXd q = phi_.transpose() * v;
  HS_PETSC(VecRestoreArrayRead(u, &a));
  return q;
}

Eigen::RowVectorXd ReducedSystem::project_row(Vec r) const { return project(r).transpose(); }

void ReducedSystem::place(const Eigen::VectorXd& q, Vec u, bool everywhere) const {
  PetscScalar* a = nullptr;
  HS_PETSC(VecGetArray(u, &a));
  if (everywhere) {
    Eigen::Map<Eigen::VectorXd>(a, phi_.rows()) = phi_ * q;
  } else {
    const Eigen::VectorXd v = phi_sample_ * q;
    for (size_t i = 0; i < sample_.size(); ++i) a[sample_[i]] = v(i);
  }
  HS_PETSC(VecRestoreArray(u, &a));
}

bool ReducedSystem::constraint_forces(Vec u, Eigen::VectorXd& p, Eigen::MatrixXd& G) {
  const double t0 = MPI_Wtime();
  const bool ok = constraints_.measure(u, 1.0);
  if (ok) {
    // The Dirichlet rows, where forces() is zero and loads() not, are zero in Phi.
    G = project_unit_forces(u);
    const std::vector<double> lambda = multipliers();
    p = G * Eigen::Map<const Eigen::VectorXd>(lambda.data(), constraints_.size());
    for (int c = 0; c < constraints_.size(); ++c)
      if (Vec w = constraints_[c].measure_load()) p += project_sampled(w);
  }
  constraint_s_ += MPI_Wtime() - t0;
  return ok;
}

bool ReducedSystem::residual(const Eigen::VectorXd& q, Vec u, Eigen::VectorXd& r,
                             Eigen::MatrixXd* tangent, Eigen::VectorXd* forces) {
  place(q, u, false);
  const double t0 = MPI_Wtime();
  const int k = size();
  r = -dead_;
  if (tangent) *tangent = Eigen::MatrixXd::Zero(k, k);
  const PetscScalar* ua = nullptr;
  HS_PETSC(VecGetArrayRead(u, &ua));
  const int n = static_cast<int>(phi_element_.empty() ? 0 : phi_element_[0].rows());
  double re[30], Ke[900];
  bool valid = true;
  for (size_t i = 0; i < elements_.size(); ++i) {
    const ElementOutput out =
        problem_.element_force(elements_[i], ua, re, tangent ? Ke : nullptr, false);
    valid &= out.valid;
    const Eigen::MatrixXd& P = phi_element_[i];
    r += weights_[i] * P.transpose() * Eigen::Map<const Eigen::VectorXd>(re, n);
    if (tangent) {
      const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>
          K(Ke, n, n);
      *tangent += weights_[i] * P.transpose() * (K * P);
    }
  }
  valid = valid && add_patches(ua, r, tangent) && add_contact(ua, r, tangent);
  HS_PETSC(VecRestoreArrayRead(u, &ua));
  element_s_ += MPI_Wtime() - t0;
  Eigen::VectorXd p;
  if (!valid || !r.allFinite() || !constraint_forces(u, p, residual_G_)) return false;
  r -= p;
  force_scale_ = std::max({dead_.norm(), p.norm(), 1e-300});
  if (forces) *forces = p;
  return r.allFinite();
}

bool ReducedSystem::add_contact(const PetscScalar* ua, Eigen::VectorXd& r, Eigen::MatrixXd* K) {
  if (!contact_) return true;
  if (!contact_->node_terms(ua, 1.0, contact_terms_)) return false;
  for (size_t i = 0; i < contact_terms_.size(); ++i) {
    const NodeContact& c = contact_terms_[i];
    if (c.gradient.isZero(0)) continue;  // farther than dhat from every obstacle
    r += phi_contact_[i].transpose() * c.gradient;
    if (K) *K += phi_contact_[i].transpose() * (c.hessian * phi_contact_[i]);
  }
  return true;
}

bool ReducedSystem::add_patches(const PetscScalar* ua, Eigen::VectorXd& r, Eigen::MatrixXd* K) {
  std::vector<double> grad, hess;
  for (const SampledPatch& patch : patches_) {
    const size_t m = patch.elements.size();
    grad.resize(12 * m);
    hess.resize(K ? 144 * m : 0);
    NodalPressure::PatchTerm term;
    if (!nodal_->patch_term(patch.node, patch.elements, ua, term, grad.data(),
                            K ? hess.data() : nullptr))
      return false;
    // g_a = sum_e dv_e/du / 4 and, with K, sum_e d2v_e/du2 / 4 on the patch's dofs.
    const Eigen::Index n = patch.phi.rows();
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    Eigen::MatrixXd H = K ? Eigen::MatrixXd::Zero(n, n) : Eigen::MatrixXd();
    for (size_t j = 0; j < m; ++j)
      for (int a = 0; a < 4; ++a) {
        const Eigen::Index ia = 3 * patch.slots[4 * j + a];
        for (int d = 0; d < 3; ++d) g(ia + d) += grad[12 * j + 3 * a + d] / 4;
        if (!K) continue;
        for (int b = 0; b < 4; ++b) {
          const Eigen::Index ib = 3 * patch.slots[4 * j + b];
          for (int d = 0; d < 3; ++d)
            for (int c = 0; c < 3; ++c)
              H(ia + d, ib + c) += hess[144 * j + 12 * (3 * a + d) + 3 * b + c] / 4;
        }
      }
    const Eigen::VectorXd Pg = patch.phi.transpose() * g;  // Phi^T g_a
    r += patch.weight * term.p * Pg;
    if (K)
      *K += patch.weight *
            (term.c * Pg * Pg.transpose() + term.p * patch.phi.transpose() * (H * patch.phi));
  }
  return true;
}

Eigen::MatrixXd ReducedSystem::unit_forces(Vec u) {
  const double t0 = MPI_Wtime();
  Eigen::MatrixXd G = project_unit_forces(u);
  constraint_s_ += MPI_Wtime() - t0;
  return G;
}

Eigen::MatrixXd ReducedSystem::project_unit_forces(Vec u) {
  const int m = constraints_.size();
  Eigen::MatrixXd G(size(), m);
  for (int c = 0; c < m; ++c) {
    constraints_[c].forces(u, work_);
    G.col(c) = project_sampled(work_);
  }
  return G;
}

Eigen::VectorXd ReducedSystem::project_sampled(Vec v) const {
  const PetscScalar* a = nullptr;
  HS_PETSC(VecGetArrayRead(v, &a));
  Eigen::VectorXd p = Eigen::VectorXd::Zero(phi_.cols());
  for (size_t i = 0; i < sample_.size(); ++i) p += a[sample_[i]] * phi_sample_.row(i).transpose();
  HS_PETSC(VecRestoreArrayRead(v, &a));
  return p;
}

void ReducedSystem::refresh_stiffness(const Eigen::VectorXd& q, Vec u, Eigen::MatrixXd& G) {
  const int k = size(), m = constraints_.size();
  G = unit_forces(u);
  unit_stiffness_.assign(m, Eigen::MatrixXd(k, k));
  const double h = 1e-7 * std::max(q.norm(), 1e-6);
  for (int j = 0; j < k; ++j) {
    Eigen::VectorXd qj = q;
    qj(j) += h;
    place(qj, u, false);
    const Eigen::MatrixXd Gj = unit_forces(u);
    for (int c = 0; c < m; ++c) unit_stiffness_[c].col(j) = (Gj.col(c) - G.col(c)) / h;
  }
  place(q, u, false);
  unit_forces_ = G;
  secant_ = Eigen::MatrixXd::Zero(k, k);
}

Eigen::MatrixXd ReducedSystem::constraint_tangent() const {
  const int k = size(), m = constraints_.size();
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(k, k);
  for (int c = 0; c < m; ++c) {
    D += constraints_[c].multiplier() * unit_stiffness_[c];
    // The liquid's weight w follows the volume, dw = (w / V) g^T du (the full model's tangent,
    // solvers/constraints/hydraulic_cavity.hpp).
    if (Vec w = constraints_[c].measure_load())
      D += project_sampled(w) / constraints_[c].measure() * unit_forces_.col(c).transpose();
  }
  return D;
}

ReducedSolve ReducedSystem::solve(Eigen::VectorXd& q, Vec u) {
  ReducedSolve out;
  Eigen::VectorXd r, p;
  Eigen::MatrixXd K;
  if (!residual(q, u, r, &K, &p)) {
    out.reason = "the starting configuration inverts an element or collapses a cavity";
    return out;
  }
  double norm = r.norm();
  for (;;) {
    const double scale = std::max({dead_.norm(), p.norm(), 1e-300});
    out.residual = norm / scale;
    // A column method's weights jump as walls cross column centres: the residual cannot be
    // asked to fall below that jump (projected, it is no larger: Phi's columns are unit).
    if (norm <= std::max(kRelativeTolerance * scale, constraints_.load_jump())) {
      out.converged = true;
      return out;
    }
    if (out.iterations == kMaxIterations) {
      out.reason = "no convergence in " + std::to_string(kMaxIterations) + " iterations";
      return out;
    }
    // The walls' stiffness per unit multiplier of an earlier configuration serves while
    // Newton converges fast (it costs k evaluations of their forces); a slow start renews it.
    if (unit_stiffness_.empty() || out.iterations == 3) {
      Eigen::MatrixXd G;
      refresh_stiffness(q, u, G);
    }
    const Eigen::VectorXd dq = (K - constraint_tangent()).partialPivLu().solve(-r);
    ++out.iterations;
    // Halve the step while it inverts an element or does not lower the residual.
    Eigen::VectorXd q_new, r_new, p_new;
    Eigen::MatrixXd K_new;
    bool accepted = false;
    double t = 1;
    for (int halving = 0; halving < 12 && !accepted; ++halving, t *= 0.5) {
      q_new = q + t * dq;
      accepted = residual(q_new, u, r_new, &K_new, &p_new) && r_new.norm() < norm;
    }
    if (!accepted) {
      place(q, u, false);
      constraints_.measure(u, 1.0);  // the constraints' measures back at q
      out.reason = "the line search found no step that lowers the residual";
      return out;
    }
    q = q_new;
    r = r_new;
    p = p_new;
    K = K_new;
    norm = r.norm();
  }
}

ReducedSolve ReducedSystem::solve_at(const Eigen::VectorXd& lambda, Eigen::VectorXd& q, Vec u) {
  const Eigen::Index sample = nearest_training_sample(lambda);
  const Eigen::VectorXd from = training_actuations_.row(sample).transpose();
  ReducedSolve out;
  for (int parts = 1; parts <= 8; parts *= 2) {
    q = training_states_.row(sample).transpose();
    out = ReducedSolve{};
    for (int i = 1; i <= parts && (i == 1 || out.converged); ++i) {
      prescribe(from + (lambda - from) * (static_cast<double>(i) / parts));
      const ReducedSolve part = solve(q, u);
      out.converged = part.converged;
      out.iterations += part.iterations;
      out.residual = part.residual;
      out.reason = part.reason;
    }
    if (out.converged) return out;
  }
  out.reason += " (also in 8 steps of the actuation from the nearest training sample)";
  return out;
}

void ReducedSystem::prescribe(const Eigen::VectorXd& lambda) {
  for (size_t a = 0; a < actuators_.size(); ++a)
    constraints_[actuators_[a]].prescribe(Constraint::Control::multiplier, lambda(a));
}

std::vector<double> ReducedSystem::multipliers() const {
  std::vector<double> lambda;
  for (int c = 0; c < constraints_.size(); ++c) lambda.push_back(constraints_[c].multiplier());
  return lambda;
}

bool ReducedSystem::balanced(const ReducedLinearization& L) const {
  return L.r.norm() <= std::max(kRelativeTolerance * L.scale, constraints_.load_jump());
}

bool ReducedSystem::linearize(const Eigen::VectorXd& q, Vec u, ReducedLinearization& L,
                              bool fresh) {
  Eigen::VectorXd p;
  if (!residual(q, u, L.r, &L.K, &p)) return false;
  L.scale = force_scale_;
  const std::vector<double> lambda = multipliers();
  const bool refresh = fresh || unit_stiffness_.empty();
  if (refresh) {
    refresh_stiffness(q, u, L.G);
  } else {
    L.G = residual_G_;  // the residual's, at the same u
    unit_forces_ = L.G;
  }
  const Eigen::MatrixXd D = constraint_tangent();
  const Eigen::VectorXd s = q - last_.q;
  if (!refresh && s.squaredNorm() > 0) {
    // Broyden: the constraints' forces changed by y along s besides what the multipliers'
    // change explains; the tangent is corrected to match that secant.
    Eigen::VectorXd y = p - last_.p;
    for (size_t c = 0; c < lambda.size(); ++c) y -= (lambda[c] - last_.lambda[c]) * last_.G.col(c);
    y -= (D + secant_) * s;
    secant_ += y * s.transpose() / s.squaredNorm();
  }
  L.K -= D + secant_;
  last_ = {q, p, lambda, L.G};
  return true;
}

}  // namespace hs
