// Closed-form solutions of the verification decks (docs/verification.md derives each one).
// Pure functions of numbers: no PETSc, no mesh. A deck names one in `exact:`; parse_deck
// checks its parameters through the registry (registry.hpp), the run builds it from them and
// the numbers of the deck it needs (elastic constants, gravity) and compares the computed
// solution with it (solvers/verification/).
#pragma once

#include <array>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

namespace hs {

using ExactParameterMap = std::map<std::string, double>;

// What an exact solution may read from the rest of the deck besides its own parameters.
struct ExactMaterial {
  std::string group;
  double E = 0, nu = 0, mu = 0, lambda = 0, density = 0;
  std::string model;  // the law's name (materials[].model)
};
struct ExactSetting {
  std::vector<ExactMaterial> materials;
  std::array<double, 3> gravity{0, 0, 0};
};

// A deck value an exact solution refuses: its key (e.g. "exact.parameters.b", "materials")
// and the reason; parse_deck reports it as "FILE: KEY: reason (line N)".
class ExactInputError : public std::invalid_argument {
 public:
  ExactInputError(std::string key, const std::string& reason)
      : std::invalid_argument(reason), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// A number the run measures on the computed solution, for solutions whose check is a
// derived quantity rather than (or as well as) the L2 error of the displacement.
enum class Measure {
  mean_displacement_z,  // mean of u_z over the owned nodes of the group
  radial_reaction,      // sum over the group's nodes of the internal force along X / |X|
};
struct MeasureRequest {
  Measure measure;
  std::string group;  // a node group of the mesh
};

class ExactSolution {
 public:
  virtual ~ExactSolution() = default;

  // The displacement at reference point X under load factor s.
  virtual std::array<double, 3> displacement(const std::array<double, 3>& X, double s) const = 0;

  // A manufactured solution's body force per unit reference volume at full load, which the
  // run adds to the deck's loads (scaled by the load factor, as gravity is); none by default.
  virtual bool has_body_force() const { return false; }
  virtual std::array<double, 3> body_force(const std::array<double, 3>& /*X*/) const {
    return {0, 0, 0};
  }

  // The mean stress -tr(sigma)/3 at full load, for solutions that give it: the run then
  // reports the error of the elements' pressure too (solvers/verification/error_norms.hpp).
  virtual bool has_pressure() const { return false; }
  virtual double pressure(const std::array<double, 3>& /*X*/) const { return 0; }

  // The measures the run takes after each load step, and the verification quantities made
  // of them (measured in the order of measures()) at load factor s; none by default.
  virtual std::vector<MeasureRequest> measures() const { return {}; }
  virtual nlohmann::json verification(const std::vector<double>& /*measured*/, double /*s*/) const {
    return nullptr;
  }
};

// The parameters of one solution, for its factory: values by name, checks that fail with
// the parameter's key.
class ExactParameters {
 public:
  ExactParameters(std::string solution, const ExactParameterMap& values)
      : solution_(std::move(solution)), values_(values) {}
  double operator[](const std::string& name) const { return values_.at(name); }
  // The value, which must be > 0 (a length, a modulus).
  double positive(const std::string& name) const;
  // The value, which must exceed parameter `smaller` (e.g. an outer radius).
  double greater_than(const std::string& name, const std::string& smaller) const;
  [[noreturn]] void fail(const std::string& name, const std::string& reason) const;

 private:
  std::string solution_;
  const ExactParameterMap& values_;
};

// The only material of the deck, or ExactInputError naming `solution` when there are
// several; the material of `group`, or ExactInputError.
const ExactMaterial& only_material(const ExactSetting& setting, const std::string& solution);
// only_material, which must be neo_hookean of nu = 0.5, or ExactInputError naming `solution`.
const ExactMaterial& only_incompressible_neo_hookean(const ExactSetting& setting,
                                                     const std::string& solution);
const ExactMaterial& material_of(const ExactSetting& setting, const std::string& group,
                                 const std::string& solution);

// Why `solution` cannot be the reference of a run on the nodes x (3 numbers a node): its
// displacement at full load at a node, or a verification quantity of a body at rest, is not a
// finite number; "" when it can. Parameters that pass their own checks can still overflow the
// closed form or divide by zero (a length of 1e-308 is above 0), which a run would otherwise
// find only at its end, in a summary it cannot write.
std::string non_finite_reference(const ExactSolution& solution, const std::vector<double>& x);

}  // namespace hs
