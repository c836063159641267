// The cavities of a scene and what they add to equation (1) of the paper: for cavity c with
// pressure lambda_c (gauge, uniform part) and, when it holds liquid, nodal weights W_c(u),
//   R(u, lambda) = f_int(u) - s f_body - sum_c lambda_c g_c(u) - sum_c W_c(u) = 0,
// g_c = dV_c/du the pressure term J_p^T (the forces of a unit pressure on the deformed walls).
// Each cavity has one more equation, its control:
//   pressure       lambda_c - p_target = 0
//   volume         V_c(u) - V_target = 0      (pneumatic or hydraulic; lambda_c is unknown)
//   sealed gas     (lambda_c + p_atm) V_c(u) - (p_0 + p_atm) V_c0 = 0
//   sealed volume  V_c(u) - V_c0 = 0
// The weight of a hydraulic cavity (always full: its liquid volume is its volume) is either
// recomputed on every configuration (coupling "converged") or, as in the paper (Section IV),
// frozen in shape at the start of a step and scaled with the volume, W = w V / v_c: the term
// J_w^T lambda_w with J_w = w / v_c and lambda_w the volume change ("linearized").
// Both linearise the weight as dW = (W / V) g^T du. docs/cavities.md derives it all.
// Cables (docs/control.md) are constraints of the same form, appended after the cavities:
// tension lambda, "volume" -L, g = -dL/du, controlled by their tension.
#pragma once

#include <petscmat.h>
#include <petscvec.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "deck/config.hpp"
#include "solvers/cable.hpp"
#include "solvers/cavity_weight.hpp"
#include "solvers/problem.hpp"

namespace hs {

enum class CavityControl { pressure, volume, sealed_gas, sealed_volume };

struct Cavity {
  CavityConfig config;
  int surface = -1;  // the Problem's pressure surface of its walls
  CavityControl control = CavityControl::pressure;
  double target = 0;                     // pressure (Pa) or volume (m^3) of the current increment
  double lambda = 0;                     // pressure: prescribed or unknown
  double volume = 0;                     // at the last evaluation
  double reference_volume = 0;           // on the undeformed mesh
  double rest_volume = 0;                // at the end of the first state
  double gas_constant = 0;               // sealed gas: (p_0 + p_atm) V_0
  std::unique_ptr<CavityWeight> weight;  // liquid with density > 0 only
  // A cable (kind "cable"): lambda its tension (N), volume -L (m), g = -dL/du its pull.
  std::unique_ptr<Cable> cable;
  Vec pull = nullptr;    // cable: -dL/du at the last residual
  Vec W = nullptr;       // its nodal weights (current)
  Vec frozen = nullptr;  // linearized: weights at the start of the step
  double frozen_volume = 0;
  bool has_weight() const { return weight != nullptr; }
  bool is_cable() const { return cable != nullptr; }
};

// The linear algebra of one Newton step: the tangent J (with -lambda H), the columns g_c and
// q_c = W_c / V_c (hydraulic), and the controls' linearisation alpha_c g_c^T du + b_c dlambda_c.
struct CavityLinearization {
  std::vector<Vec> g, q;  // q empty Vec (nullptr) for cavities without weight
  std::vector<double> alpha, b;
};

class CavitySystem {
 public:
  // Collective. Checks every cavity surface (closed, manifold, enclosing positive volume).
  CavitySystem(const Config& config, Problem& problem, const Mesh& mesh, const Distribution& dist);
  ~CavitySystem();
  CavitySystem(const CavitySystem&) = delete;
  CavitySystem& operator=(const CavitySystem&) = delete;

  int size() const { return static_cast<int>(cavities_.size()); }
  Cavity& operator[](int c) { return cavities_[c]; }
  const Cavity& operator[](int c) const { return cavities_[c]; }
  std::vector<double> pressures() const;
  void set_pressures(const std::vector<double>& lambda);

  // R(u, lambda; s) and the controls c (size()). Returns false on an inverted element or a
  // cavity whose volume is not positive (collapse_reason() then names it).
  bool residual(Vec u, double s, Vec R, std::vector<double>& c);
  // After a residual() that returned false: why, if a cavity's volume was <= 0; else "".
  std::string collapse_reason() const;
  // Tangent and linearisation at (u, lambda; s), after a residual() at the same point.
  bool linearize(Vec u, double s, Mat J, CavityLinearization& lin);
  // The "volume" of constraint c on configuration u: a cavity's enclosed volume, a cable's
  // length with a minus sign (collective).
  double measure(int c, Vec u) const;
  // Scale of each control equation for convergence tests and the line search.
  double control_scale(int c) const;

  // Linearized coupling: freezes each hydraulic cavity's weights at configuration u.
  void freeze_weights(Vec u, double s);
  bool linearized() const { return linearized_; }

  // Fluid-weight seconds and calls so far, and what ran (for summary.json).
  double fluid_weight_seconds() const { return weight_seconds_; }
  // Seconds spent building the constraints: cavity volumes and cable lengths, their
  // gradients g (J_p^T), the weight columns q, the cables' stiffness (not the FEM assembly).
  double constraint_build_seconds() const { return build_seconds_; }
  int fluid_weight_calls() const { return weight_calls_; }
  nlohmann::json parts() const;
  nlohmann::json report() const;  // [{name, kind, volume, pressure, fluid_weight_total}]

 private:
  void update_weights(Vec u, double s);

  Problem& problem_;
  std::vector<Cavity> cavities_;
  Vec weights_ = nullptr;  // sum of the cavities' W, the Problem's extra load
  bool linearized_ = false;
  int collapsed_ = -1;  // the first cavity with volume <= 0 at the last residual(), or -1
  double weight_seconds_ = 0;
  double build_seconds_ = 0;
  int weight_calls_ = 0;
};

}  // namespace hs
