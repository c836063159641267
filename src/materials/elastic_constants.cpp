#include "materials/elastic_constants.hpp"

namespace hs {

ElasticConstants elastic_constants_from_E_nu(double E, double nu) {
  ElasticConstants c;
  c.E = E;
  c.nu = nu;
  c.mu = c.E / (2 * (1 + c.nu));
  c.lambda = c.E * c.nu / ((1 + c.nu) * (1 - 2 * c.nu));
  return c;
}

ElasticConstants elastic_constants_from_mu_nu(double mu, double nu) {
  ElasticConstants c;
  c.mu = mu;
  c.nu = nu;
  c.E = 2 * c.mu * (1 + c.nu);
  c.lambda = 2 * c.mu * c.nu / (1 - 2 * c.nu);
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

double parse_poisson_ratio(const DeckReader& r, const YAML::Node& node, const std::string& key) {
  const auto nu = required(r, node, key, "nu");
  const double value = r.number(nu, child_key(key, "nu"));
  require(value > -1 && value < 0.5, r, nu, child_key(key, "nu"),
          "must lie in (-1, 0.5), got " + format_number(value) +
              " (0.5 is incompressible, beyond a displacement formulation)");
  return value;
}

ElasticConstants parse_elastic_constants(const DeckReader& r, const YAML::Node& node,
                                         const std::string& key) {
  const bool engineering = node["E"] || node["nu"], lame = node["mu"] || node["lambda"];
  if (engineering && lame) r.fail(key, node, "give either E and nu or mu and lambda, not both");
  if (!engineering && !lame)
    r.fail(key, node, "elastic constants missing: give E and nu, or mu and lambda");
  if (engineering) {
    const auto E = required(r, node, key, "E");
    const double E_value = r.number(E, child_key(key, "E"));
    require(E_value > 0, r, E, child_key(key, "E"), "must be > 0, got " + format_number(E_value));
    return elastic_constants_from_E_nu(E_value, parse_poisson_ratio(r, node, key));
  }
  const auto mu = required(r, node, key, "mu"), lambda = required(r, node, key, "lambda");
  const double mu_value = r.number(mu, child_key(key, "mu"));
  const double lambda_value = r.number(lambda, child_key(key, "lambda"));
  require(mu_value > 0, r, mu, child_key(key, "mu"), "must be > 0, got " + format_number(mu_value));
  const double bulk = lambda_value + 2 * mu_value / 3;
  require(bulk > 0, r, lambda, child_key(key, "lambda"),
          "gives bulk modulus lambda + 2 mu / 3 = " + format_number(bulk) + ", must be > 0");
  return elastic_constants_from_lame(mu_value, lambda_value);
}

void print_number(YAML::Emitter& out, const std::string& key, double value) {
  out << YAML::Key << key << YAML::Value << format_number(value);
}

bool ElasticLaw::given_as_E_nu() const {
  const ElasticConstants& c = constants_;
  return c.mu == c.E / (2 * (1 + c.nu)) && c.lambda == c.E * c.nu / ((1 + c.nu) * (1 - 2 * c.nu));
}

void ElasticLaw::print(YAML::Emitter& out) const {
  const bool from_E_nu = given_as_E_nu();
  print_number(out, from_E_nu ? "E" : "mu", from_E_nu ? constants_.E : constants_.mu);
  print_number(out, from_E_nu ? "nu" : "lambda", from_E_nu ? constants_.nu : constants_.lambda);
}

std::string ElasticLaw::derived_values() const {
  return given_as_E_nu()
             ? "mu = " + format_number(constants_.mu) +
                   ", lambda = " + format_number(constants_.lambda)
             : "E = " + format_number(constants_.E) + ", nu = " + format_number(constants_.nu);
}

}  // namespace hs
