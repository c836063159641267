#include "solvers/constraints/cable.hpp"

namespace hs {

Cable::Cable(const CableConfig& config, Problem& problem, const std::string& deck_path)
    : Constraint(config.name), problem_(problem), path_(config, problem, deck_path) {
  pull_ = VecHandle(problem.create_vector());
  const VecHandle zero(problem.create_vector());
  reference_measure = measure = rest_measure = -path_.length(zero);
  control = Control::multiplier;
  first_state_multiplier = config.force;  // the first state ramps it like a cavity pressure
}

double Cable::measure_at(Vec u) const { return -path_.length(u); }

void Cable::forces(Vec u, Vec g) const {
  path_.pull_direction(u, g);
  problem_.zero_constrained(g);
}

void Cable::add_load(Vec u, double /*s*/, Vec load) {
  path_.pull_direction(u, pull_);
  HS_PETSC(VecAXPY(load, lambda, pull_));
}

void Cable::set_stiffness(Vec u, Problem& problem) { path_.set_stiffness(u, lambda, problem); }

nlohmann::json Cable::report() const {
  nlohmann::json j;
  j["name"] = name();
  j["kind"] = kind();
  j["length"] = -measure;
  j["pull"] = measure - rest_measure;  // shortening since the end of the first state
  j["force"] = lambda;
  return j;
}

}  // namespace hs
