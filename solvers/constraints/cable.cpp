#include "solvers/constraints/cable.hpp"

namespace hs {

Cable::Cable(const CableConfig& config, ConstraintContext& context)
    : Constraint(config.name),
      problem_(context.problem),
      path_(config, context.problem, context.deck_path()) {
  pull_ = VecHandle(problem_.create_vector());
  const VecHandle zero(problem_.create_vector());
  set_reference_measure(-path_.length(zero));
  set_first_state(config.force, std::nullopt);  // ramped like a cavity pressure
}

double Cable::measure_at(Vec u) const { return -path_.length(u); }

void Cable::forces(Vec u, Vec g) const {
  path_.pull_direction(u, g);
  problem_.zero_constrained(g);
}

void Cable::mark_reads(Vec marks) const {
  for (size_t i = 0; i < path_.points(); ++i)
    for (PetscInt dof : path_.dofs(i))
      if (dof >= 0) HS_PETSC(VecSetValue(marks, dof, 1.0, INSERT_VALUES));
  HS_PETSC(VecAssemblyBegin(marks));
  HS_PETSC(VecAssemblyEnd(marks));
}

void Cable::add_load(Vec u, double /*s*/, Vec load) {
  path_.pull_direction(u, pull_);
  HS_PETSC(VecAXPY(load, multiplier(), pull_));
}

void Cable::set_stiffness(Vec u, Problem& problem) {
  path_.set_stiffness(u, multiplier(), problem);
}

nlohmann::json Cable::report() const {
  nlohmann::json j;
  j["name"] = name();
  j["kind"] = kind();
  j["length"] = -measure();
  j["pull"] = measure() - rest_measure();  // shortening since the end of the first state
  j["force"] = multiplier();
  return j;
}

void Cable::add_history(HistoryRow& row) const {
  row.add("cable_" + name() + "_force_N", multiplier());
  row.add("cable_" + name() + "_pull_m", measure() - rest_measure());
}

}  // namespace hs
