#include "solvers/reduced/model_fit.hpp"

#include <cmath>

#include "common/error.hpp"
#include "deck/config_fingerprint.hpp"

namespace hs {
namespace {

// Why this run cannot be reduced, or "". A training's full solves run on any number of ranks;
// a model answers on one.
std::string unreducible(const Config& config, const Problem& problem,
                        const ConstraintSet& constraints, bool training) {
  if (!training && problem.distribution().size != 1)
    return "a reduced model runs on one rank (this run has " +
           std::to_string(problem.distribution().size) + ")";
  if (!config.control) return "a reduced model needs a control section (its actuators)";
  if (problem.has_volume_multipliers())
    return "an exactly incompressible material (nu = 0.5) keeps its volumes by multipliers "
           "that the reduced model does not carry; give it nu 0.4999 (within 0.1 % of it)";
  if (problem.has_open_surface_pressure())
    return "a deck's follower pressure load (loads.pressure) is not reduced; cavities are";
  if (const ObstacleContact* contact = problem.contact(); contact && contact->has_friction())
    return "contact with friction is not reduced (its lag is a state of the path)";
  if (problem.self_contact())
    return "self-contact is not reduced (its pairs couple nodes that no element does)";
  for (const auto& e : config.control->effectors)
    if (!e.obstacle.empty() || !e.between.empty())
      return "effector '" + e.name +
             "' is a contact force, which the reduced model does not "
             "answer (positions only)";
  for (int c = 0; c < constraints.size(); ++c) {
    bool driven = false;
    for (const auto& a : config.control->actuators) driven |= a.constraint == constraints[c].name();
    if (!driven)
      return "'" + constraints[c].name() +
             "' is not an actuator: every cavity and cable must be driven by the controller";
  }
  return "";
}

}  // namespace

std::string reduced_physics(const Config& config) {
  Config physics = config;
  physics.control.reset();
  physics.states.clear();
  physics.tip.reset();
  physics.exact = ExactConfig{};
  physics.time = TimeConfig{};
  physics.solver = SolverConfig{};
  return config_fingerprint(physics);
}

void record_mesh(const Problem& problem, ReducedModel& model) {
  const Distribution& dist = problem.distribution();
  std::vector<double> x(dist.x.size());
  for (int64_t n = 0; n < dist.num_local(); ++n)
    for (int d = 0; d < 3; ++d) x[3 * dist.old_of_local[n] + d] = dist.x[3 * n + d];
  model.nodes = dist.num_global();
  model.tets = dist.num_global_tets;
  model.order = dist.order;
  model.coordinate_checksum = coordinate_checksum(x);
}

void check_reducible(const Config& config, const Problem& problem,
                     const ConstraintSet& constraints) {
  const std::string why = unreducible(config, problem, constraints, true);
  if (!why.empty()) throw InputError(config.deck_path + ": hydrosoft reduce: " + why);
}

void check_model_fits(const Config& config, const Problem& problem,
                      const ConstraintSet& constraints, const ReducedModel& model,
                      const std::string& path) {
  const std::string where = config.deck_path + ": control.reduced_model '" + path + "': ";
  const std::string why = unreducible(config, problem, constraints, false);
  if (!why.empty()) throw InputError(where + why);
  ReducedModel run;
  record_mesh(problem, run);
  if (run.nodes != model.nodes || run.tets != model.tets || run.order != model.order)
    throw InputError(where + "made for a mesh of " + std::to_string(model.nodes) + " nodes, " +
                     std::to_string(model.tets) + " P" + std::to_string(model.order) +
                     " tetrahedra; this run's has " + std::to_string(run.nodes) + ", " +
                     std::to_string(run.tets) + " P" + std::to_string(run.order));
  if (std::abs(run.coordinate_checksum - model.coordinate_checksum) >
      1e-9 * std::max(1.0, std::abs(model.coordinate_checksum)))
    throw InputError(where + "made for a mesh of the same size but other coordinates");
  if (reduced_physics(config) != model.physics)
    throw InputError(where + "trained on other physics (deck '" + model.deck +
                     "': materials, boundary, loads, cavities or cables differ)");
  std::vector<std::string> names;
  for (const auto& a : config.control->actuators) names.push_back(a.constraint);
  if (names != model.actuators) throw InputError(where + "trained for other actuators");
}

}  // namespace hs
