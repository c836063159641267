#include "solvers/constraints/cavity.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "fluidweight/fluidweight.hpp"
#include "solvers/gathered_surface.hpp"
#include "solvers/problem.hpp"

namespace hs {
namespace {

std::string format_si(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", x);
  return text;
}

// Refuses (on every rank) a cavity whose faces do not form a closed, manifold, consistently
// oriented surface, naming the first bad edge by its mesh node numbers.
void check_cavity_surface(const Problem& problem, const std::string& deck,
                          const std::string& group) {
  const GatheredSurface s = gather_surface(problem.distribution(), group, 0, problem.comm());
  std::string error;
  if (!s.faces.empty()) {
    fluidweight::SurfaceMesh corners;
    corners.vertices = s.x;
    for (size_t f = 0; f < s.faces.size() / s.nodes_per_face; ++f)
      for (int a = 0; a < 3; ++a) corners.triangles.push_back(s.faces[f * s.nodes_per_face + a]);
    try {
      fluidweight::check_closed_surface(corners, "cavity '" + group + "'");
    } catch (const fluidweight::InputError& e) {
      error = deck + ": " + e.what() + " (the surface's own node numbers, 0-based; mesh nodes " +
              std::to_string(s.mesh_nodes.front()) + ".." + std::to_string(s.mesh_nodes.back()) +
              ")";
    }
  }
  throw_together<InputError>(error, problem.comm());
}

}  // namespace

Cavity::Cavity(const CavityConfig& config, ConstraintContext& context)
    : Constraint(config.group), problem_(context.problem), config_(config) {
  const std::string& deck_path = context.deck_path();
  Problem& problem = context.problem;
  check_cavity_surface(problem, deck_path, config.group);
  surface_ = problem.add_cavity_surface(config.group);
  const VecHandle zero(problem.create_vector());
  const double volume = problem.enclosed_volume(surface_, zero);
  if (!(volume > 0))
    throw InputError(deck_path + ": cavity '" + config.group + "': its faces enclose a volume of " +
                     std::to_string(volume) +
                     " m^3; a cavity's wall faces point into the cavity, out of the body, and "
                     "enclose a positive volume (is the group an outer boundary?)");
  set_reference_measure(volume);
  set_first_state(config.pressure, config.added_volume);
  // Walls cannot pass through each other (there is no contact), so a volume target <= 0
  // has no solution; refuse it before any solve.
  if (config.added_volume && !(volume + *config.added_volume > 0))
    throw InputError(deck_path + ": cavity '" + config.group + "': added_volume " +
                     format_si(*config.added_volume) + " m^3 would leave it a volume of " +
                     format_si(volume + *config.added_volume) + " m^3 (it holds " +
                     format_si(volume) + " m^3 undeformed); a cavity's volume must stay > 0");
}

double Cavity::measure_at(Vec u) const { return problem_.enclosed_volume(surface_, u); }

void Cavity::forces(Vec u, Vec g) const { problem_.volume_gradient(surface_, u, g); }

void Cavity::apply_multiplier(Problem& problem) {
  problem.set_surface_pressure(surface_, multiplier());
}

nlohmann::json Cavity::report() const {
  nlohmann::json j;
  j["name"] = name();
  j["kind"] = kind();
  j["volume"] = measure();
  j["volume_ml"] = measure() * 1e6;
  j["added_volume_ml"] = (measure() - rest_measure()) * 1e6;
  j["pressure"] = multiplier();
  double total[3] = {0, 0, 0};  // |sum of the nodal weights| on the current configuration
  if (Vec W = measure_load()) HS_PETSC(VecStrideSumAll(W, total));
  j["fluid_weight_total"] = std::hypot(total[0], total[1], total[2]);
  return j;
}

void Cavity::add_history(HistoryRow& row) const {
  const nlohmann::json j = report();  // collective (the liquid weight's sum)
  const std::string prefix = "cavity_" + name() + "_";
  row.add(prefix + "pressure_Pa", multiplier());
  row.add(prefix + "volume_m3", measure());
  row.add(prefix + "added_volume_m3", measure() - rest_measure());
  if (measure_load()) row.add(prefix + "fluid_weight_N", j["fluid_weight_total"].get<double>());
}

std::string Cavity::collapse_reason() const {
  if (measure() > 0) return "";
  return "cavity '" + name() + "' reaches a volume of " + format_si(measure()) +
         " m^3 <= 0 (its walls pass through each other)";
}

std::string Cavity::ramp_failure_note() const {
  if (control() != Control::multiplier || target() == 0) return "";
  std::ostringstream note;
  note << "cavity '" << name() << "' was at " << target()
       << " Pa on a pressure ramp (past a pressure peak or a buckling of the walls there is no "
          "equilibrium under pressure control: prescribe added_volume to pass it)";
  return note.str();
}

}  // namespace hs
