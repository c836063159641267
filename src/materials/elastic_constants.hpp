// The elastic constants shared by every law: read from a material's map as E, nu or as
// mu, lambda (their key table), checked, the other pair derived; printed back as the pair given.
// ElasticLaw holds them for the laws whose parameters are these constants (plus, for some,
// keys of their own).
#pragma once

#include <yaml-cpp/yaml.h>

#include <memory>
#include <string>
#include <vector>

#include "common/deck_reader.hpp"
#include "materials/law_keys.hpp"
#include "materials/material.hpp"

namespace hs {

// Whether (mu, lambda) is what E, nu give (then the deck gave E, nu): the derived pair,
// converted back, may differ in the last bit, so the given one is printed.
bool given_as_E_nu(const ElasticConstants& c);

// nu = 0.5, exact incompressibility: the laws take lambda = kIncompressiblePenalty mu, the
// penalty of the augmented Lagrangian whose multipliers keep every patch's volume
// (solvers/nodal_pressure.hpp, docs/formulation.md "Exactly incompressible bodies").
inline constexpr double kIncompressiblePenalty = 5000;
inline bool incompressible(const ElasticConstants& c) { return c.nu == 0.5; }

// The Poisson ratio's bound: in (-1, 0.5], 0.5 being incompressible.
Limit poisson_ratio_limit();

// The keys E, nu, mu, lambda of a law whose parameters S are ElasticConstants or derive from
// them: each read as given (E, mu > 0; nu in (-1, 0.5]), printed as the pair the deck gave.
// resolve_elastic_constants then checks the pair and derives the other.
template <class S>
LawKeyTable<S> elastic_constant_keys() {
  const auto engineering = [](const S& s) { return given_as_E_nu(s); };
  const auto lame = [](const S& s) { return !given_as_E_nu(s); };
  return {
      LawKeys::number_key<S>("E", &S::E, above(0), "Young's modulus (Pa), with `nu`")
          .defaults_to("required without `mu`, `lambda`")
          .printed_when(engineering),
      LawKeys::number_key<S>("nu", &S::nu, poisson_ratio_limit(),
                             "Poisson's ratio, with `E`; 0.5 is exact incompressibility (P1 "
                             "meshes, docs/formulation.md)")
          .defaults_to("required without `mu`, `lambda`")
          .printed_when(engineering),
      LawKeys::number_key<S>("mu", &S::mu, above(0), "Lamé's shear modulus μ (Pa), with `lambda`")
          .defaults_to("required without `E`, `nu`")
          .printed_when(lame),
      LawKeys::number_key<S>("lambda", &S::lambda, any_number(),
                             "Lamé's λ (Pa), with `mu`; the bulk modulus λ + 2μ/3 must be > 0")
          .defaults_to("required without `E`, `nu`")
          .printed_when(lame),
  };
}

// The constants `read` holds once the keys of the map `node` at `key` are read: exactly one of
// the pairs (E, nu), (mu, lambda) given, the other derived; throws through r.fail as
// "FILE: KEY: reason" when a pair is missing, mixed or non-physical.
ElasticConstants resolve_elastic_constants(const DeckReader& r, const YAML::Node& node,
                                           const std::string& key, const ElasticConstants& read);

// The pair (E, nu) given, (mu, lambda) derived:
//   mu = E / (2 (1 + nu)),  lambda = E nu / ((1 + nu)(1 - 2 nu))  (kIncompressiblePenalty mu at
//   nu = 0.5).
ElasticConstants elastic_constants_from_E_nu(double E, double nu);
// mu and nu given (a law whose shear modulus is its own parameter), E and lambda derived:
//   E = 2 mu (1 + nu),  lambda = 2 mu nu / (1 - 2 nu).
ElasticConstants elastic_constants_from_mu_nu(double mu, double nu);
// The pair (mu, lambda) given, (E, nu) derived:
//   E = mu (3 lambda + 2 mu) / (lambda + mu),  nu = lambda / (2 (lambda + mu)).
ElasticConstants elastic_constants_from_lame(double mu, double lambda);

// A law whose parameters are the elastic constants, and possibly keys of its own.
class ElasticLaw : public MaterialLaw {
 public:
  explicit ElasticLaw(const ElasticConstants& constants) : constants_(constants) {}
  const ElasticConstants& elastic_constants() const override { return constants_; }
  // The derived pair, e.g. "mu = 1e+05, lambda = 4.9e+06".
  std::string derived_values() const override;

 protected:
  ElasticConstants constants_;
};

// A pointwise law of the elastic constants alone: P, dP/dF from (mu, lambda, H).
using ElasticPointwise = StressResult (*)(double mu, double lambda, const Mat3& H,
                                          bool with_tangent);

// The registered law of such a function: its file declares the function and one alias,
//   inline constexpr char kNeoHookeanName[] = "neo_hookean";
//   using NeoHookeanLaw = ConstantsOnlyLaw<kNeoHookeanName, neo_hookean, true>;
// LambdaLnJ: psi has the volumetric term lambda/2 (ln J)^2 (volumetric_modulus() = lambda).
template <const char* Name, ElasticPointwise Pointwise, bool LambdaLnJ = false>
class ConstantsOnlyLaw : public ElasticLaw {
 public:
  static constexpr const char* kName = Name;
  using Parameters = ElasticConstants;
  static const LawKeyTable<Parameters>& keys() {
    static const LawKeyTable<Parameters> keys = elastic_constant_keys<Parameters>();
    return keys;
  }
  static std::shared_ptr<const MaterialLaw> make(const DeckReader& r, const YAML::Node& node,
                                                 const std::string& key, const Parameters& read) {
    return std::make_shared<ConstantsOnlyLaw>(resolve_elastic_constants(r, node, key, read));
  }
  const Parameters& parameters() const { return constants_; }

  using ElasticLaw::ElasticLaw;
  std::string name() const override { return kName; }
  StressResult stress(const Mat3& H, bool with_tangent) const override {
    return Pointwise(constants_.mu, constants_.lambda, H, with_tangent);
  }
  bool has_volumetric_term() const override { return LambdaLnJ; }
  double volumetric_modulus() const override { return LambdaLnJ ? constants_.lambda : 0.0; }
};

}  // namespace hs
