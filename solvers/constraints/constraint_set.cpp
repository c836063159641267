#include "solvers/constraints/constraint_set.hpp"

#include <algorithm>

#include "solvers/constraints/cavity.hpp"
#include "solvers/constraints/constraint_kinds.hpp"

namespace hs {

ConstraintSet::ConstraintSet(const Config& config, Problem& problem)
    : problem_(problem), constraints_(make_constraints(config, problem)) {
  bool any_load = false;
  for (const auto& c : constraints_) {
    any_load |= c->adds_load();
    linearized_ |= c->frozen_coupling();
  }
  if (any_load) {
    loads_ = VecHandle(problem.create_vector());
    problem.set_extra_load(loads_);
  }
}

ConstraintSet::~ConstraintSet() {
  problem_.set_extra_load(nullptr);
  constraints_.clear();
}

int ConstraintSet::find(const std::string& name) const {
  for (int k = 0; k < size(); ++k)
    if (constraints_[k]->name() == name) return k;
  return -1;
}

std::vector<double> ConstraintSet::multipliers() const {
  std::vector<double> lambda;
  for (const auto& c : constraints_) lambda.push_back(c->multiplier());
  return lambda;
}

void ConstraintSet::set_multipliers(const std::vector<double>& lambda) {
  for (size_t k = 0; k < constraints_.size(); ++k) constraints_[k]->set_multiplier(lambda[k]);
}

std::vector<Constraint::State> ConstraintSet::snapshot() const {
  std::vector<Constraint::State> states;
  for (const auto& c : constraints_) states.push_back(c->snapshot());
  return states;
}

void ConstraintSet::restore(const std::vector<Constraint::State>& states) {
  for (size_t k = 0; k < constraints_.size(); ++k) constraints_[k]->restore(states[k]);
}

ConstraintSet::Point ConstraintSet::point() const {
  Point p{snapshot(), VecHandle()};
  if (loads_) {
    HS_PETSC(VecDuplicate(loads_, p.loads.out()));
    HS_PETSC(VecCopy(loads_, p.loads));
  }
  return p;
}

void ConstraintSet::return_to(const Point& point) {
  restore(point.states);
  for (auto& c : constraints_) c->apply_multiplier(problem_);
  if (loads_) HS_PETSC(VecCopy(point.loads, loads_));
}

void ConstraintSet::freeze_weights(Vec u, double s) {
  for (auto& c : constraints_) c->freeze(u, s);
}

bool ConstraintSet::update(Vec u, double s) {
  collapsed_ = -1;
  const double t0 = MPI_Wtime();
  for (size_t k = 0; k < constraints_.size(); ++k) {
    Constraint& c = *constraints_[k];
    c.apply_multiplier(problem_);
    c.update_measure(u);
    if (collapsed_ < 0 && !c.collapse_reason().empty()) collapsed_ = static_cast<int>(k);
  }
  build_seconds_ += MPI_Wtime() - t0;
  // A cavity whose walls have passed through each other (volume <= 0: nothing stops them,
  // there is no contact) is outside the domain like an inverted element; its liquid's weight
  // is not computed there.
  if (collapsed_ < 0 && loads_) {
    HS_PETSC(VecSet(loads_, 0.0));
    for (auto& c : constraints_) c->add_load(u, s, loads_);
  }
  return collapsed_ < 0;
}

bool ConstraintSet::residual(Vec u, double s, Vec R, std::vector<double>& control) {
  control.resize(constraints_.size());
  const bool in_domain = update(u, s);
  const bool ok = problem_.residual(u, s, R) && in_domain;
  for (size_t k = 0; k < constraints_.size(); ++k) control[k] = constraints_[k]->control_residual();
  return ok;
}

bool ConstraintSet::loads(Vec u, double s, Vec f) {
  if (!update(u, s)) return false;
  problem_.cavity_pressure_load(u, f);
  if (loads_) HS_PETSC(VecAXPY(f, 1.0, loads_));
  return true;
}

bool ConstraintSet::linearize(Vec u, double s, Mat J, ConstraintLinearization& lin) {
  // Stiffness that no element holds (a cable's tension turning with its path) is given to
  // the problem before the tangent is assembled.
  for (auto& c : constraints_) c->set_stiffness(u, problem_);
  const bool ok = problem_.jacobian(u, s, J);
  const double t0 = MPI_Wtime();
  const size_t m = constraints_.size();
  if (lin.g.size() != m) {
    lin.g.resize(m);
    lin.q.resize(m);
    for (size_t k = 0; k < m; ++k) {
      lin.g.reset(k, problem_.create_vector());
      if (constraints_[k]->measure_load()) lin.q.reset(k, problem_.create_vector());
    }
  }
  lin.alpha.assign(m, 0.0);
  lin.b.assign(m, 0.0);
  for (size_t k = 0; k < m; ++k) {
    const Constraint& c = *constraints_[k];
    c.forces(u, lin.g[k]);
    if (lin.q[k]) {  // dw = (w / q) g^T du: the load follows the measure
      HS_PETSC(VecAXPBY(lin.q[k], 1.0 / c.measure(), 0.0, c.measure_load()));
      problem_.zero_constrained(lin.q[k]);
    }
    c.control_linearization(lin.alpha[k], lin.b[k]);
  }
  build_seconds_ += MPI_Wtime() - t0;
  return ok;
}

bool ConstraintSet::fluid_weight_load(Vec f) const {
  bool any = false;
  for (const auto& c : constraints_) {
    // The load that follows the measure of a constraint with a liquid is its weight.
    if (!c->fluid_weight() || !c->measure_load()) continue;
    if (!any) HS_PETSC(VecSet(f, 0.0));
    HS_PETSC(VecAXPY(f, 1.0, c->measure_load()));
    any = true;
  }
  return any;
}

bool ConstraintSet::symmetric() const {
  return std::all_of(constraints_.begin(), constraints_.end(),
                     [](const auto& c) { return c->symmetric_stiffness(); });
}

bool ConstraintSet::holds_pressures() const {
  return std::all_of(constraints_.begin(), constraints_.end(), [](const auto& c) {
    return dynamic_cast<const Cavity*>(c.get()) &&
           c->control() == Constraint::Control::multiplier && !c->adds_load() && !c->fluid_weight();
  });
}

std::string ConstraintSet::collapse_reason() const {
  return collapsed_ < 0 ? "" : constraints_[collapsed_]->collapse_reason();
}

double ConstraintSet::load_jump() const {
  double jump = 0;
  for (const auto& k : constraints_) jump = std::max(jump, k->load_jump());
  return jump;
}

double ConstraintSet::fluid_weight_seconds() const {
  double seconds = 0;
  for (const auto& c : constraints_)
    if (const FluidWeightUse* use = c->fluid_weight()) seconds += use->seconds;
  return seconds;
}

int ConstraintSet::fluid_weight_calls() const {
  int calls = 0;
  for (const auto& c : constraints_)
    if (const FluidWeightUse* use = c->fluid_weight()) calls += use->calls;
  return calls;
}

nlohmann::json ConstraintSet::parts() const {
  nlohmann::json p;
  for (const std::string& family : constraint_families()) p[family] = 0;
  int weighted = 0;
  bool cuda = false;
  std::string method;
  for (const auto& c : constraints_) {
    p[c->family()] = p[c->family()].get<int>() + 1;
    const FluidWeightUse* use = c->fluid_weight();
    if (!use) continue;
    ++weighted;
    cuda |= use->device == "cuda";
    method = use->method;
  }
  p["fluid_weight"]["cavities"] = weighted;
  p["fluid_weight"]["device"] = weighted == 0 ? "none" : (cuda ? "cuda" : "cpu");
  p["fluid_weight"]["method"] = weighted == 0 ? "none" : method;
  p["fluid_weight"]["calls"] = fluid_weight_calls();
  p["cuda_context"] = cuda;
  return p;
}

nlohmann::json ConstraintSet::report() const {
  nlohmann::json r;
  for (const std::string& family : constraint_families()) r[family] = nlohmann::json::array();
  for (const auto& c : constraints_) r[c->family()].push_back(c->report());
  return r;
}

void ConstraintSet::add_history(HistoryRow& row) const {
  for (const auto& c : constraints_) c->add_history(row);
}

double ConstraintSet::added_volume() const {
  double added = 0;
  for (const auto& c : constraints_)
    if (measures_volume(*c)) added += c->measure() - c->rest_measure();
  return added;
}

double ConstraintSet::volume_change() const {
  double change = 0;
  for (const auto& c : constraints_)
    if (measures_volume(*c)) change += c->measure() - c->reference_measure();
  return change;
}

bool measures_volume(const Constraint& c) { return std::string(c.units().measure) == "m3"; }

}  // namespace hs
