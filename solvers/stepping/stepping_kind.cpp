#include "solvers/stepping/stepping_kind.hpp"

namespace hs {

SteppingKind stepping_kind_of(const Config& config) {
  if (config.control) return SteppingKind::control;
  if (!config.cavities.empty() || !config.cables.empty() || !config.states.empty() || config.tip)
    return SteppingKind::states;
  return config.time.type == TimeType::dynamic ? SteppingKind::dynamic : SteppingKind::static_load;
}

std::string stepping_kind_name(SteppingKind kind) {
  switch (kind) {
    case SteppingKind::static_load:
      return "static";
    case SteppingKind::dynamic:
      return "dynamic";
    case SteppingKind::states:
      return "states";
    case SteppingKind::control:
      return "control";
  }
  return "static";
}

}  // namespace hs
