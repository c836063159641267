#include <utility>

#include "solvers/reduced/training_stepper.hpp"
#include "solvers/stepping/control_stepper.hpp"
#include "solvers/stepping/dynamic_states_stepper.hpp"
#include "solvers/stepping/dynamic_stepper.hpp"
#include "solvers/stepping/states_stepper.hpp"
#include "solvers/stepping/static_stepper.hpp"
#include "solvers/stepping/stepper.hpp"

namespace hs {

std::unique_ptr<Stepper> make_stepper(const StepperParts& p, InteractiveIo io) {
  switch (stepping_kind_of(p.config)) {
    case SteppingKind::static_load:
      return std::make_unique<StaticStepper>(p.config, p.problem, p.solver, p.stats);
    case SteppingKind::dynamic:
      return std::make_unique<DynamicStepper>(p.config, p.problem, p.solver, p.stats);
    case SteppingKind::states:
      return std::make_unique<StatesStepper>(p.config, p.problem, *p.constraints, p.solver, p.stats,
                                             *p.recorder);
    case SteppingKind::dynamic_states:
      return std::make_unique<DynamicStatesStepper>(p.config, p.problem, *p.constraints, p.solver,
                                                    p.stats, *p.recorder);
    case SteppingKind::control:
      return std::make_unique<ControlStepper>(p.config, p.problem, *p.constraints, *p.bordered,
                                              p.stats, *p.recorder, std::move(io));
    case SteppingKind::reduce:
      return std::make_unique<TrainingStepper>(p.config, p.problem, *p.constraints, *p.bordered,
                                               p.stats, *p.recorder);
  }
  return nullptr;
}

}  // namespace hs
