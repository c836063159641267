#include "solvers/constraints/constraint_kinds.hpp"

#include <mpi.h>

#include "solvers/constraints/cable.hpp"
#include "solvers/constraints/capstan_cable.hpp"
#include "solvers/constraints/hydraulic_cavity.hpp"
#include "solvers/constraints/pressure_limited_cavity.hpp"
#include "solvers/constraints/sealed_cavity.hpp"
#include "solvers/problem.hpp"

namespace hs {
namespace {

template <class Kind, class Deck>
std::unique_ptr<Constraint> make(const Deck& deck, ConstraintContext& context) {
  return std::make_unique<Kind>(deck, context);
}

struct CavityKindEntry {
  CavityKind kind;
  std::unique_ptr<Constraint> (*make)(const CavityConfig&, ConstraintContext&);
};

// One line per cavity kind of the deck (kCavityKindNames).
const CavityKindEntry kCavityKinds[] = {
    {CavityKind::pneumatic, make<Cavity>},
    {CavityKind::hydraulic, make<HydraulicCavity>},
    {CavityKind::sealed_gas, make<SealedCavity>},
    {CavityKind::sealed_volume, make<SealedCavity>},
    {CavityKind::pressure_limited, make<PressureLimitedCavity>},
};

// A cable is frictionless, or turns through its eyelets with Coulomb friction.
std::unique_ptr<Constraint> make_cable(const CableConfig& cable, ConstraintContext& context) {
  if (cable.friction > 0) return make<CapstanCable>(cable, context);
  return make<Cable>(cable, context);
}

}  // namespace

int ConstraintContext::next_weighing_rank() {
  int ranks = 1;
  MPI_Comm_size(problem.comm(), &ranks);
  return weighing_++ % ranks;
}

std::vector<std::unique_ptr<Constraint>> make_constraints(const Config& config, Problem& problem) {
  ConstraintContext context(problem, config);
  std::vector<std::unique_ptr<Constraint>> list;
  for (const CavityConfig& cavity : config.cavities)
    for (const CavityKindEntry& entry : kCavityKinds)
      if (entry.kind == cavity.kind) list.push_back(entry.make(cavity, context));
  for (const CableConfig& cable : config.cables) list.push_back(make_cable(cable, context));
  return list;
}

const std::vector<std::string>& constraint_families() {
  static const std::vector<std::string> families = {"cavities", "cables"};
  return families;
}

}  // namespace hs
