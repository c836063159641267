#include "solvers/constraints/constraint_set.hpp"

#include <algorithm>

#include "solvers/constraints/cable.hpp"
#include "solvers/constraints/capstan_cable.hpp"
#include "solvers/constraints/hydraulic_cavity.hpp"
#include "solvers/constraints/sealed_cavity.hpp"

namespace hs {
namespace {

// The deck's constraints, one line per kind. The fluid-weight module of each weighing
// hydraulic cavity runs on its own rank, round robin.
std::vector<std::unique_ptr<Constraint>> make_constraints(const Config& config, Problem& problem) {
  int ranks = 1;
  MPI_Comm_size(problem.comm(), &ranks);
  int weighing = 0;
  const std::string& deck = config.deck_path;
  std::vector<std::unique_ptr<Constraint>> list;
  for (const CavityConfig& c : config.cavities) {
    switch (c.kind) {
      case CavityKind::pneumatic:
        list.push_back(std::make_unique<Cavity>(c, problem, deck));
        break;
      case CavityKind::hydraulic:
        list.push_back(
            std::make_unique<HydraulicCavity>(c, problem, config.gravity, weighing % ranks, deck));
        weighing += HydraulicCavity::weighs(c, config.gravity);
        break;
      case CavityKind::sealed_gas:
      case CavityKind::sealed_volume:
        list.push_back(std::make_unique<SealedCavity>(c, problem, deck));
        break;
    }
  }
  for (const CableConfig& c : config.cables) {
    if (c.friction > 0)
      list.push_back(std::make_unique<CapstanCable>(c, problem, deck));
    else
      list.push_back(std::make_unique<Cable>(c, problem, deck));
  }
  return list;
}

}  // namespace

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
  for (const auto& c : constraints_) lambda.push_back(c->lambda);
  return lambda;
}

void ConstraintSet::set_multipliers(const std::vector<double>& lambda) {
  for (size_t k = 0; k < constraints_.size(); ++k) constraints_[k]->lambda = lambda[k];
}

void ConstraintSet::freeze_weights(Vec u, double s) {
  for (auto& c : constraints_) c->freeze(u, s);
}

bool ConstraintSet::residual(Vec u, double s, Vec R, std::vector<double>& control) {
  control.resize(constraints_.size());
  collapsed_ = -1;
  const double t0 = MPI_Wtime();
  for (size_t k = 0; k < constraints_.size(); ++k) {
    Constraint& c = *constraints_[k];
    c.apply_multiplier(problem_);
    c.measure = c.measure_at(u);
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
  const bool ok = problem_.residual(u, s, R) && collapsed_ < 0;
  for (size_t k = 0; k < constraints_.size(); ++k) control[k] = constraints_[k]->control_residual();
  return ok;
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
      HS_PETSC(VecAXPBY(lin.q[k], 1.0 / c.measure, 0.0, c.measure_load()));
      problem_.zero_constrained(lin.q[k]);
    }
    c.control_linearization(lin.alpha[k], lin.b[k]);
  }
  build_seconds_ += MPI_Wtime() - t0;
  return ok;
}

int ConstraintSet::cavity_count() const {
  return static_cast<int>(std::count_if(constraints_.begin(), constraints_.end(),
                                        [](const auto& c) { return c->is_cavity(); }));
}

bool ConstraintSet::fluid_weight_load(Vec f) const {
  bool any = false;
  for (const auto& c : constraints_) {
    // A cavity's load that follows its measure is its liquid's weight.
    if (!c->is_cavity() || !c->measure_load()) continue;
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

std::string ConstraintSet::collapse_reason() const {
  return collapsed_ < 0 ? "" : constraints_[collapsed_]->collapse_reason();
}

double ConstraintSet::fluid_weight_seconds() const {
  double seconds = 0;
  for (const auto& c : constraints_)
    if (const auto* h = dynamic_cast<const HydraulicCavity*>(c.get()))
      seconds += h->weight_seconds();
  return seconds;
}

int ConstraintSet::fluid_weight_calls() const {
  int calls = 0;
  for (const auto& c : constraints_)
    if (const auto* h = dynamic_cast<const HydraulicCavity*>(c.get())) calls += h->weight_calls();
  return calls;
}

nlohmann::json ConstraintSet::parts() const {
  nlohmann::json p;
  const auto cavities = std::count_if(constraints_.begin(), constraints_.end(),
                                      [](const auto& c) { return c->is_cavity(); });
  p["cavities"] = cavities;
  p["cables"] = constraints_.size() - cavities;
  int weighted = 0;
  bool cuda = false;
  std::string method;
  for (const auto& c : constraints_) {
    const auto* h = dynamic_cast<const HydraulicCavity*>(c.get());
    if (!h || !h->has_weight()) continue;
    ++weighted;
    cuda |= std::string(h->device()) == "cuda";
    method = h->method();
  }
  p["fluid_weight"]["cavities"] = weighted;
  p["fluid_weight"]["device"] = weighted == 0 ? "none" : (cuda ? "cuda" : "cpu");
  p["fluid_weight"]["method"] = weighted == 0 ? "none" : method;
  p["fluid_weight"]["calls"] = fluid_weight_calls();
  p["cuda_context"] = cuda;
  return p;
}

nlohmann::json ConstraintSet::report() const {
  nlohmann::json r = {{"cavities", nlohmann::json::array()}, {"cables", nlohmann::json::array()}};
  for (const auto& c : constraints_)
    r[c->is_cavity() ? "cavities" : "cables"].push_back(c->report());
  return r;
}

void ConstraintSet::add_history(HistoryRow& row) const {
  for (const auto& c : constraints_) {
    const nlohmann::json j = c->report();  // collective (the fluid weight's sum)
    if (c->is_cavity()) {
      const std::string prefix = "cavity_" + c->name() + "_";
      row.add(prefix + "pressure_Pa", j["pressure"].get<double>());
      row.add(prefix + "volume_m3", j["volume"].get<double>());
      row.add(prefix + "added_volume_m3", c->measure - c->rest_measure);
      if (c->measure_load()) row.add(prefix + "fluid_weight_N", j["fluid_weight_total"]);
    } else {
      const std::string prefix = "cable_" + c->name() + "_";
      row.add(prefix + "force_N", c->lambda);
      row.add(prefix + "pull_m", c->measure - c->rest_measure);
    }
  }
}

}  // namespace hs
