#include "solvers/cavity_system.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/error.hpp"

namespace hs {
namespace {

std::string format_si(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", x);
  return text;
}

CavityControl control_of(const CavityConfig& c) {
  if (c.kind == "sealed_gas") return CavityControl::sealed_gas;
  if (c.kind == "sealed_volume") return CavityControl::sealed_volume;
  return c.added_volume ? CavityControl::volume : CavityControl::pressure;
}

// Refuses a cavity whose faces do not form a closed, manifold, consistently oriented surface,
// naming the first bad edge by its mesh node numbers.
void check_cavity_surface(const Mesh& mesh, const std::string& deck, const std::string& group) {
  const auto& faces = mesh.surfaces.at(group);
  const int npf = mesh.nodes_per_face();
  fluidweight::SurfaceMesh corners;
  corners.vertices = mesh.x;
  for (size_t f = 0; f < faces.size() / npf; ++f)
    for (int a = 0; a < 3; ++a) corners.triangles.push_back(static_cast<int>(faces[f * npf + a]));
  try {
    fluidweight::check_closed_surface(corners, "cavity '" + group + "'");
  } catch (const fluidweight::InputError& e) {
    throw InputError(deck + ": " + e.what() + " (mesh node numbers, 0-based)");
  }
}

}  // namespace

CavitySystem::CavitySystem(const Config& config, Problem& problem, const Mesh& mesh,
                           const Distribution& dist)
    : problem_(problem) {
  int size = 1;
  MPI_Comm_size(problem.comm(), &size);
  Vec zero = problem.create_vector();
  int owner = 0;
  cavities_.resize(config.cavities.size());
  for (size_t i = 0; i < config.cavities.size(); ++i) {
    Cavity& c = cavities_[i];
    c.config = config.cavities[i];
    check_cavity_surface(mesh, config.deck_path, c.config.group);
    c.surface = problem.add_cavity_surface(c.config.group);
    c.reference_volume = problem.enclosed_volume(c.surface, zero);
    if (!(c.reference_volume > 0))
      throw InputError(config.deck_path + ": cavity '" + c.config.group +
                       "': its faces enclose a volume of " + std::to_string(c.reference_volume) +
                       " m^3; a cavity's wall faces point into the cavity, out of the body, and "
                       "enclose a positive volume (is the group an outer boundary?)");
    c.volume = c.rest_volume = c.reference_volume;
    c.control = control_of(c.config);
    // Walls cannot pass through each other (there is no contact), so a volume target <= 0
    // has no solution; refuse it before any solve.
    if (c.control == CavityControl::volume && !(c.reference_volume + *c.config.added_volume > 0))
      throw InputError(config.deck_path + ": cavity '" + c.config.group + "': added_volume " +
                       format_si(*c.config.added_volume) + " m^3 would leave it a volume of " +
                       format_si(c.reference_volume + *c.config.added_volume) + " m^3 (it holds " +
                       format_si(c.reference_volume) +
                       " m^3 undeformed); a cavity's volume must stay > 0");
    if (c.control == CavityControl::sealed_gas) {
      c.lambda = c.config.initial_pressure;
      c.gas_constant = (c.config.initial_pressure + c.config.atmospheric_pressure) * c.volume;
    }
    const double g = std::hypot(config.gravity[0], config.gravity[1], config.gravity[2]);
    if (c.config.kind == "hydraulic" && c.config.density > 0 && g > 0) {
      c.weight = std::make_unique<CavityWeight>(mesh, dist, c.config, config.gravity,
                                                owner++ % size, problem.comm());
      c.W = problem.create_vector();
      if (c.config.fluid_weight.coupling == "linearized") {
        c.frozen = problem.create_vector();
        linearized_ = true;
      }
    }
  }
  // Cables after the cavities: tension-controlled constraints with "volume" -L.
  for (const auto& cc : config.cables) {
    Cavity c;
    c.config.group = cc.name;
    c.config.kind = "cable";
    c.config.pressure = cc.force;  // the first state ramps it like a cavity pressure
    c.cable = std::make_unique<Cable>(cc, problem, config.deck_path);
    c.pull = problem.create_vector();
    c.reference_volume = c.volume = c.rest_volume = -c.cable->length(zero);
    c.control = CavityControl::pressure;
    cavities_.push_back(std::move(c));
  }
  HS_PETSC(VecDestroy(&zero));
  const bool any_weight = std::any_of(cavities_.begin(), cavities_.end(), [](const Cavity& c) {
    return c.has_weight() || c.is_cable();
  });
  if (any_weight) {
    weights_ = problem.create_vector();
    problem.set_extra_load(weights_);
  }
}

CavitySystem::~CavitySystem() {
  problem_.set_extra_load(nullptr);
  VecDestroy(&weights_);
  for (auto& c : cavities_) {
    VecDestroy(&c.W);
    VecDestroy(&c.frozen);
    VecDestroy(&c.pull);
  }
}

std::vector<double> CavitySystem::pressures() const {
  std::vector<double> p;
  for (const auto& c : cavities_) p.push_back(c.lambda);
  return p;
}

void CavitySystem::set_pressures(const std::vector<double>& lambda) {
  for (size_t i = 0; i < cavities_.size(); ++i) cavities_[i].lambda = lambda[i];
}

void CavitySystem::update_weights(Vec u, double s) {
  if (!weights_) return;
  HS_PETSC(VecSet(weights_, 0.0));
  for (auto& c : cavities_) {
    if (!c.has_weight()) continue;
    if (c.frozen) {  // the paper's J_w: the frozen distribution times V / v_c
      HS_PETSC(VecAXPBY(c.W, c.volume / c.frozen_volume, 0.0, c.frozen));
    } else {
      HS_PETSC(VecSet(c.W, 0.0));
      c.weight->add_weight(u, s, c.W);
      weight_seconds_ += c.weight->seconds();
      ++weight_calls_;
    }
    HS_PETSC(VecAXPY(weights_, 1.0, c.W));
  }
  // A cable's tension acts on its points as lambda (-dL/du), a load like the weights.
  for (auto& c : cavities_)
    if (c.is_cable()) {
      c.cable->pull_direction(u, c.pull);
      HS_PETSC(VecAXPY(weights_, c.lambda, c.pull));
    }
}

void CavitySystem::freeze_weights(Vec u, double s) {
  for (auto& c : cavities_) {
    if (!c.frozen) continue;
    HS_PETSC(VecSet(c.frozen, 0.0));
    c.weight->add_weight(u, s, c.frozen);
    weight_seconds_ += c.weight->seconds();
    ++weight_calls_;
    c.frozen_volume = problem_.enclosed_volume(c.surface, u);
  }
}

bool CavitySystem::residual(Vec u, double s, Vec R, std::vector<double>& control) {
  control.resize(cavities_.size());
  collapsed_ = -1;
  const double t0 = MPI_Wtime();
  for (size_t i = 0; i < cavities_.size(); ++i) {
    Cavity& c = cavities_[i];
    if (c.is_cable()) {
      c.volume = -c.cable->length(u);
      continue;
    }
    problem_.set_surface_pressure(c.surface, c.lambda);
    c.volume = problem_.enclosed_volume(c.surface, u);
    if (!(c.volume > 0) && collapsed_ < 0) collapsed_ = static_cast<int>(i);
  }
  build_seconds_ += MPI_Wtime() - t0;
  // A cavity whose walls have passed through each other (volume <= 0: nothing stops them,
  // there is no contact) is outside the domain like an inverted element; its liquid's weight
  // is not computed there.
  if (collapsed_ < 0) update_weights(u, s);
  const bool ok = problem_.residual(u, s, R) && collapsed_ < 0;
  for (size_t i = 0; i < cavities_.size(); ++i) {
    const Cavity& c = cavities_[i];
    switch (c.control) {
      case CavityControl::pressure:
        control[i] = c.lambda - c.target;
        break;
      case CavityControl::volume:
        control[i] = c.volume - c.target;
        break;
      case CavityControl::sealed_gas:
        control[i] = (c.lambda + c.config.atmospheric_pressure) * c.volume - c.gas_constant;
        break;
      case CavityControl::sealed_volume:
        control[i] = c.volume - c.reference_volume;
        break;
    }
  }
  return ok;
}

bool CavitySystem::linearize(Vec u, double s, Mat J, CavityLinearization& lin) {
  // A cable's tension turning with its path stiffens the body: lambda d2L/du2, which couples
  // the nodes of consecutive cable points (blocks the cable registered with the problem,
  // given before the tangent is assembled).
  for (const auto& c : cavities_)
    if (c.is_cable()) c.cable->set_stiffness(u, c.lambda, problem_);
  const bool ok = problem_.jacobian(u, s, J);
  const double t0 = MPI_Wtime();
  const size_t m = cavities_.size();
  if (lin.g.size() != m) {
    lin.g.resize(m, nullptr);
    lin.q.resize(m, nullptr);
    for (size_t i = 0; i < m; ++i) {
      lin.g[i] = problem_.create_vector();
      if (cavities_[i].has_weight()) lin.q[i] = problem_.create_vector();
    }
  }
  lin.alpha.assign(m, 0.0);
  lin.b.assign(m, 0.0);
  for (size_t i = 0; i < m; ++i) {
    const Cavity& c = cavities_[i];
    if (c.is_cable()) {
      c.cable->pull_direction(u, lin.g[i]);
      problem_.zero_constrained(lin.g[i]);
    } else {
      problem_.volume_gradient(c.surface, u, lin.g[i]);
    }
    if (lin.q[i]) {  // dW = (W / V) g^T du: the weight follows the volume
      HS_PETSC(VecAXPBY(lin.q[i], 1.0 / c.volume, 0.0, c.W));
      problem_.zero_constrained(lin.q[i]);
    }
    switch (c.control) {
      case CavityControl::pressure:
        lin.b[i] = 1;
        break;
      case CavityControl::volume:
      case CavityControl::sealed_volume:
        lin.alpha[i] = 1;
        break;
      case CavityControl::sealed_gas:
        lin.alpha[i] = c.lambda + c.config.atmospheric_pressure;
        lin.b[i] = c.volume;
        break;
    }
  }
  build_seconds_ += MPI_Wtime() - t0;
  return ok;
}

double CavitySystem::measure(int i, Vec u) const {
  const Cavity& c = cavities_[i];
  return c.is_cable() ? -c.cable->length(u) : problem_.enclosed_volume(c.surface, u);
}

std::string CavitySystem::collapse_reason() const {
  if (collapsed_ < 0) return "";
  const Cavity& c = cavities_[collapsed_];
  return "cavity '" + c.config.group + "' reaches a volume of " + format_si(c.volume) +
         " m^3 <= 0 (its walls pass through each other)";
}

double CavitySystem::control_scale(int i) const {
  const Cavity& c = cavities_[i];
  switch (c.control) {
    case CavityControl::pressure:
      return std::max(std::abs(c.target), 1.0);
    case CavityControl::sealed_gas:
      return c.gas_constant;
    default:
      return c.reference_volume;
  }
}

nlohmann::json CavitySystem::parts() const {
  nlohmann::json p;
  const auto cables = std::count_if(cavities_.begin(), cavities_.end(),
                                    [](const Cavity& c) { return c.is_cable(); });
  p["cavities"] = cavities_.size() - cables;
  p["cables"] = cables;
  int weighted = 0;
  bool cuda = false;
  std::string method;
  for (const auto& c : cavities_)
    if (c.has_weight()) {
      ++weighted;
      cuda |= std::string(c.weight->device()) == "cuda";
      method = c.config.fluid_weight.method;
    }
  p["fluid_weight"]["cavities"] = weighted;
  p["fluid_weight"]["device"] = weighted == 0 ? "none" : (cuda ? "cuda" : "cpu");
  p["fluid_weight"]["method"] = weighted == 0 ? "none" : method;
  p["fluid_weight"]["calls"] = weight_calls_;
  p["cuda_context"] = cuda;
  return p;
}

nlohmann::json CavitySystem::report() const {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : cavities_) {
    nlohmann::json j;
    j["name"] = c.config.group;
    j["kind"] = c.config.kind;
    if (c.is_cable()) {
      j["length"] = -c.volume;
      j["pull"] = c.volume - c.rest_volume;  // shortening since the end of the first state
      j["force"] = c.lambda;
      list.push_back(j);
      continue;
    }
    j["volume"] = c.volume;
    j["volume_ml"] = c.volume * 1e6;
    j["added_volume_ml"] = (c.volume - c.rest_volume) * 1e6;
    j["pressure"] = c.lambda;
    double total[3] = {0, 0, 0};  // |sum of the nodal weights| on the current configuration
    if (c.W) HS_PETSC(VecStrideSumAll(c.W, total));
    j["fluid_weight_total"] = std::hypot(total[0], total[1], total[2]);
    if (c.has_weight()) j["fluid_weight_volume"] = c.weight->measured_volume();
    list.push_back(j);
  }
  return list;
}

}  // namespace hs
