#include "materials/elastic_constants.hpp"

namespace hs {

ElasticConstants elastic_constants_from_E_nu(double E, double nu) {
  ElasticConstants c;
  c.E = E;
  c.nu = nu;
  c.mu = c.E / (2 * (1 + c.nu));
  c.lambda =
      c.nu == 0.5 ? kIncompressiblePenalty * c.mu : c.E * c.nu / ((1 + c.nu) * (1 - 2 * c.nu));
  return c;
}

ElasticConstants elastic_constants_from_mu_nu(double mu, double nu) {
  ElasticConstants c;
  c.mu = mu;
  c.nu = nu;
  c.E = 2 * c.mu * (1 + c.nu);
  c.lambda = c.nu == 0.5 ? kIncompressiblePenalty * c.mu : 2 * c.mu * c.nu / (1 - 2 * c.nu);
  return c;
}

ElasticConstants elastic_constants_from_lame(double mu, double lambda) {
  ElasticConstants c;
  c.mu = mu;
  c.lambda = lambda;
  c.E = c.mu * (3 * c.lambda + 2 * c.mu) / (c.lambda + c.mu);
  c.nu = c.lambda / (2 * (c.lambda + c.mu));
  return c;
}

Limit poisson_ratio_limit() {
  return {"in (-1, 0.5]", [](double nu) {
            if (nu > -1 && nu <= 0.5) return std::string();
            return "must lie in (-1, 0.5] (0.5: incompressible), got " + format_number(nu);
          }};
}

ElasticConstants resolve_elastic_constants(const DeckReader& r, const YAML::Node& node,
                                           const std::string& key, const ElasticConstants& read) {
  const bool engineering = node["E"] || node["nu"], lame = node["mu"] || node["lambda"];
  if (engineering && lame) r.fail(key, node, "give either E and nu or mu and lambda, not both");
  if (!engineering && !lame)
    r.fail(key, node, "elastic constants missing: give E and nu, or mu and lambda");
  if (engineering) {
    required(r, node, key, "E");
    required(r, node, key, "nu");
    return elastic_constants_from_E_nu(read.E, read.nu);
  }
  required(r, node, key, "mu");
  const YAML::Node lambda = required(r, node, key, "lambda");
  const double bulk = read.lambda + 2 * read.mu / 3;
  require(bulk > 0, r, lambda, child_key(key, "lambda"),
          "gives bulk modulus lambda + 2 mu / 3 = " + format_number(bulk) + ", must be > 0");
  return elastic_constants_from_lame(read.mu, read.lambda);
}

bool given_as_E_nu(const ElasticConstants& c) {
  const ElasticConstants engineering = elastic_constants_from_E_nu(c.E, c.nu);
  return c.mu == engineering.mu && c.lambda == engineering.lambda;
}

std::string ElasticLaw::derived_values() const {
  if (constants_.nu == 0.5)
    return "mu = " + format_number(constants_.mu) +
           ", incompressible: lambda = " + format_number(constants_.lambda) +
           " as the penalty of the volume multipliers";
  return given_as_E_nu(constants_)
             ? "mu = " + format_number(constants_.mu) +
                   ", lambda = " + format_number(constants_.lambda)
             : "E = " + format_number(constants_.E) + ", nu = " + format_number(constants_.nu);
}

}  // namespace hs
