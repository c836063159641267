#include "solvers/stepping/stepping_kind.hpp"

namespace hs {

SteppingKind stepping_kind_of(const Config& config) {
  if (config.training) return SteppingKind::reduce;
  if (config.control) return SteppingKind::control;
  const bool dynamic = config.time.type == TimeType::dynamic;
  if (!config.cavities.empty() || !config.cables.empty() || !config.states.empty() || config.tip)
    return dynamic ? SteppingKind::dynamic_states : SteppingKind::states;
  return dynamic ? SteppingKind::dynamic : SteppingKind::static_load;
}

std::string stepping_kind_name(SteppingKind kind) {
  switch (kind) {
    case SteppingKind::static_load:
      return "static";
    case SteppingKind::dynamic:
      return "dynamic";
    case SteppingKind::states:
      return "states";
    case SteppingKind::dynamic_states:
      return "dynamic_states";
    case SteppingKind::control:
      return "control";
    case SteppingKind::reduce:
      return "reduce";
  }
  return "static";
}

}  // namespace hs
