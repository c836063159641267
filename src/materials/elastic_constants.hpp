// The elastic constants shared by every law: read from a material's map as E, nu or as
// mu, lambda (docs/decks.md), checked, the other pair derived; printed back as the pair given.
// ElasticLaw holds them for the laws whose parameters are these constants (plus, for some,
// keys of their own).
#pragma once

#include <yaml-cpp/yaml.h>

#include <memory>
#include <string>
#include <vector>

#include "common/deck_reader.hpp"
#include "materials/material.hpp"

namespace hs {

// The keys parse_elastic_constants reads.
inline const std::vector<std::string> kElasticConstantKeys = {"E", "nu", "mu", "lambda"};

// Exactly one of the pairs (E, nu), (mu, lambda) from the map `node` at `key`; throws through
// r.fail as "FILE: KEY: reason" when a pair is missing, mixed or non-physical.
ElasticConstants parse_elastic_constants(const DeckReader& r, const YAML::Node& node,
                                         const std::string& key);

// The Poisson ratio `nu` of the map `node` at `key`, required, in (-1, 0.5): the one check of nu,
// for the pair (E, nu) and for a law whose shear modulus comes from keys of its own (yeoh).
double parse_poisson_ratio(const DeckReader& r, const YAML::Node& node, const std::string& key);

// The pair (E, nu) given, (mu, lambda) derived:
//   mu = E / (2 (1 + nu)),  lambda = E nu / ((1 + nu)(1 - 2 nu)).
ElasticConstants elastic_constants_from_E_nu(double E, double nu);
// mu and nu given (a law whose shear modulus is its own parameter), E and lambda derived:
//   E = 2 mu (1 + nu),  lambda = 2 mu nu / (1 - 2 nu).
ElasticConstants elastic_constants_from_mu_nu(double mu, double nu);
// The pair (mu, lambda) given, (E, nu) derived:
//   E = mu (3 lambda + 2 mu) / (lambda + mu),  nu = lambda / (2 (lambda + mu)).
ElasticConstants elastic_constants_from_lame(double mu, double lambda);

// `key: value` with the shortest text that reads back as exactly `value`.
void print_number(YAML::Emitter& out, const std::string& key, double value);

// A law whose parameters are the elastic constants, and possibly keys of its own (it then
// extends print and derived_values).
class ElasticLaw : public MaterialLaw {
 public:
  explicit ElasticLaw(const ElasticConstants& constants) : constants_(constants) {}
  const ElasticConstants& elastic_constants() const override { return constants_; }
  // The pair the deck gave, E and nu or mu and lambda.
  void print(YAML::Emitter& out) const override;
  // The derived pair, e.g. "mu = 1e+05, lambda = 4.9e+06".
  std::string derived_values() const override;

 protected:
  // Whether (mu, lambda) is what E, nu give (then the deck gave E, nu): the derived pair,
  // converted back, may differ in the last bit, so the given one is printed.
  bool given_as_E_nu() const;

  ElasticConstants constants_;
};

// A pointwise law of the elastic constants alone: P, dP/dF from (mu, lambda, H).
using ElasticPointwise = StressResult (*)(double mu, double lambda, const Mat3& H,
                                          bool with_tangent);

// The registered law of such a function: its file declares the function and one alias,
//   inline constexpr char kNeoHookeanName[] = "neo_hookean";
//   using NeoHookeanLaw = ConstantsOnlyLaw<kNeoHookeanName, neo_hookean>;
template <const char* Name, ElasticPointwise Pointwise>
class ConstantsOnlyLaw : public ElasticLaw {
 public:
  static constexpr const char* kName = Name;
  static std::vector<std::string> keys() { return kElasticConstantKeys; }
  static std::shared_ptr<const MaterialLaw> parse(const DeckReader& r, const YAML::Node& node,
                                                  const std::string& key) {
    return std::make_shared<ConstantsOnlyLaw>(parse_elastic_constants(r, node, key));
  }

  using ElasticLaw::ElasticLaw;
  std::string name() const override { return kName; }
  StressResult stress(const Mat3& H, bool with_tangent) const override {
    return Pointwise(constants_.mu, constants_.lambda, H, with_tangent);
  }
};

}  // namespace hs
