#include "solvers/bordered_system.hpp"

#include "solvers/multi_solve.hpp"
#include "solvers/petsc_check.hpp"
#include "solvers/solver_options.hpp"

namespace hs {

BorderedSystem::BorderedSystem(const Problem& problem, const ConstraintSet& constraints,
                               Order order)
    : m_(constraints.size()), order_(order), a_(problem.create_vector()) {
  for (int c = 0; c < m_; ++c) {
    Y_.push_back(problem.create_vector());
    Z_.push_back(constraints[c].measure_load() ? problem.create_vector() : nullptr);
  }
}

bool BorderedSystem::solve(KSP ksp, Vec R, const ConstraintLinearization& lin, int* iterations) {
  std::vector<Vec> rhs{R}, solutions{a_};
  columns_.clear();
  weighted_.clear();
  for (int c = 0; c < m_; ++c) {
    rhs.push_back(lin.g[c]);
    solutions.push_back(Y_[c]);
    columns_.push_back(Y_[c]);
    if (order_ == Order::per_constraint && Z_[c]) {
      rhs.push_back(lin.q[c]);
      solutions.push_back(Z_[c]);
    }
  }
  for (int c = 0; c < m_; ++c) {
    if (!Z_[c]) continue;
    if (order_ == Order::g_then_q) {
      rhs.push_back(lin.q[c]);
      solutions.push_back(Z_[c]);
    }
    columns_.push_back(Z_[c]);
    weighted_.push_back(c);
  }
  return solve_columns(ksp, rhs, solutions, iterations);
}

void BorderedSystem::solve_residual(KSP ksp, Vec R) {
  const OptionsScope scope(reinterpret_cast<PetscObject>(ksp));
  HS_PETSC(KSPSolve(ksp, R, a_));
}

void BorderedSystem::factor_dense(const ConstraintLinearization& lin,
                                  const std::vector<bool>& held) {
  const int n = size();
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  std::vector<PetscScalar> dots(n);
  for (int c = 0; c < m_; ++c) {  // alpha_c g_c^T du + b_c dlambda_c = -c_c
    if (!held.empty() && held[c]) {
      S(c, c) = 1;
      continue;
    }
    HS_PETSC(VecMDot(lin.g[c], n, columns_.data(), dots.data()));
    for (int k = 0; k < n; ++k) S(c, k) = lin.alpha[c] * dots[k];
    S(c, c) += lin.b[c];
  }
  for (size_t w = 0; w < weighted_.size(); ++w) {  // eta_h - g_h^T du = 0
    const int row = m_ + static_cast<int>(w);
    HS_PETSC(VecMDot(lin.g[weighted_[w]], n, columns_.data(), dots.data()));
    for (int k = 0; k < n; ++k) S(row, k) = dots[k];
    S(row, row) -= 1;
  }
  lu_.compute(S);
}

Eigen::VectorXd BorderedSystem::residual_rhs(const ConstraintLinearization& lin,
                                             const std::vector<double>& c,
                                             const std::vector<bool>& held) const {
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(size());
  PetscScalar ga = 0;
  for (int i = 0; i < m_; ++i) {
    if (!held.empty() && held[i]) continue;
    HS_PETSC(VecDot(lin.g[i], a_, &ga));
    rhs(i) = -c[i] + lin.alpha[i] * ga;
  }
  for (size_t w = 0; w < weighted_.size(); ++w) {
    HS_PETSC(VecDot(lin.g[weighted_[w]], a_, &ga));
    rhs(m_ + static_cast<int>(w)) = ga;
  }
  return rhs;
}

void BorderedSystem::step(const Eigen::VectorXd& zeta, Vec out) {
  HS_PETSC(VecCopy(a_, out));
  HS_PETSC(VecScale(out, -1.0));
  HS_PETSC(VecMAXPY(out, size(), zeta.data(), columns_.data()));
}

void BorderedSystem::response(const Eigen::VectorXd& zeta, Vec out) {
  HS_PETSC(VecSet(out, 0.0));
  HS_PETSC(VecMAXPY(out, size(), zeta.data(), columns_.data()));
}

bool BorderedSystem::load_responses(KSP ksp, const std::vector<Vec>& f,
                                    const ConstraintLinearization& lin,
                                    const std::vector<bool>& held, const std::vector<Vec>& out,
                                    Eigen::MatrixXd& zeta) {
  if (!solve_columns(ksp, f, out)) return false;
  const int n = size(), N = static_cast<int>(f.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, N);
  std::vector<PetscScalar> dots(N);
  for (int i = 0; i < m_; ++i) {
    if (!held.empty() && held[i]) continue;
    if (N) HS_PETSC(VecMDot(lin.g[i], N, out.data(), dots.data()));
    for (int j = 0; j < N; ++j) rhs(i, j) = -lin.alpha[i] * dots[j];
  }
  for (size_t w = 0; w < weighted_.size(); ++w) {
    if (N) HS_PETSC(VecMDot(lin.g[weighted_[w]], N, out.data(), dots.data()));
    for (int j = 0; j < N; ++j) rhs(m_ + static_cast<int>(w), j) = -dots[j];
  }
  zeta = lu_.solve(rhs);
  for (int j = 0; j < N; ++j) HS_PETSC(VecMAXPY(out[j], n, zeta.col(j).data(), columns_.data()));
  return true;
}

}  // namespace hs
