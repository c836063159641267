#include "solvers/stepping/secant_predictor.hpp"

#include <utility>

#include "solvers/petsc_check.hpp"

namespace hs {

SecantPredictor::SecantPredictor(const Problem& problem)
    : u_last_(problem.create_vector()), saved_(problem.create_vector()) {}

void SecantPredictor::predict(Vec u, std::vector<double>& multipliers, double t) {
  HS_PETSC(VecCopy(u, saved_));
  lambda_saved_ = multipliers;
  if (!has_last_ || t_ == t_last_) return;
  const double k = (t - t_) / (t_ - t_last_);
  HS_PETSC(VecAXPBY(u, -k, 1 + k, u_last_));  // u <- (1 + k) u - k u_last
  for (size_t c = 0; c < multipliers.size(); ++c)
    multipliers[c] = (1 + k) * multipliers[c] - k * lambda_last_[c];
}

void SecantPredictor::accept(double t) {
  HS_PETSC(VecCopy(saved_, u_last_));
  lambda_last_ = lambda_saved_;
  t_last_ = t_;
  t_ = t;
  has_last_ = true;
}

void SecantPredictor::reject(Vec u, std::vector<double>& multipliers) const {
  HS_PETSC(VecCopy(saved_, u));
  multipliers = lambda_saved_;
}

void SecantPredictor::start_path() {
  t_ = 0;
  has_last_ = false;
}

void SecantPredictor::resume(double t, double t_last, bool has_last,
                             std::vector<double> lambda_last) {
  t_ = t;
  t_last_ = t_last;
  has_last_ = has_last;
  lambda_last_ = std::move(lambda_last);
}

}  // namespace hs
