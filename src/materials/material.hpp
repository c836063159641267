// Constitutive laws behind one interface. A law is an object made by the registry
// (materials/registry.hpp) from its YAML map; each law lives in one file (its name, its
// parameters' key table, psi, P and dP/dF), so nothing outside that file switches on the
// model. Its pointwise functions stay pure (functions of H = F - I and numbers), so that each
// can be checked against finite differences (tests/materials).
#pragma once

#include <Eigen/Dense>
#include <string>

namespace hs {

using Mat3 = Eigen::Matrix3d;
// dP_ij / dF_kl stored at (3*i + j, 3*k + l) (row-major flattening of both).
using Tangent = Eigen::Matrix<double, 9, 9>;

struct StressResult {
  Mat3 P;      // first Piola-Kirchhoff stress
  Tangent A;   // dP/dF (0 when not asked for)
  double psi;  // strain energy density
};

// The elastic constants every law of this code takes: E, nu or mu, lambda in the deck, the
// other pair derived (materials/elastic_constants.hpp).
struct ElasticConstants {
  double E = 0, nu = 0;
  double mu = 0, lambda = 0;
};

class MaterialLaw {
 public:
  virtual ~MaterialLaw() = default;
  // The deck's model name, e.g. neo_hookean.
  virtual std::string name() const = 0;
  // Stress, energy density and (if with_tangent) tangent at the displacement gradient
  // H = F - I, which element routines have: small strains keep their relative precision (F - I
  // would leave an absolute error of 1e-16, a stress error of 1e-16 times the stiffness, a
  // residual floor for small loads). For det F <= 0, and wherever a law is not defined, psi is
  // +inf and P, A are NaN: callers treat that as an inverted element.
  virtual StressResult stress(const Mat3& H, bool with_tangent) const = 0;
  // Cauchy stress sigma = P F^T / J, used for output (von Mises).
  virtual Mat3 cauchy_stress(const Mat3& F) const;
  // Whether dP/dF is positive definite at every H (a linear law): the solvers may then use
  // CG. A finite-strain law's tangent can be indefinite away from equilibrium (compression
  // past a full Newton step), where CG breaks down.
  virtual bool tangent_always_definite() const { return false; }
  // Whether psi and P are finite at every finite F with det F > 0: where they are, a body's
  // stresses are finite once every element keeps its orientation (the check before a control
  // answer, solvers/control_run.cpp). Gent's are not past the chains' limit.
  virtual bool finite_wherever_oriented() const { return true; }
  // Whether the law is of small strains (linear elasticity): the F-bar element then takes its
  // linearisation, B-bar, so that the law stays linear (fem/fbar_element.cpp).
  virtual bool small_strain() const { return false; }
  // Whether psi has the volumetric term k/2 (ln J)^2, or k/2 (tr eps)^2 for a small-strain law
  // (materials/volumetric_term.hpp): the term a nodal-pressure element integrates per node;
  // and its k (0 without the term).
  virtual bool has_volumetric_term() const { return false; }
  virtual double volumetric_modulus() const { return 0; }
  // The elastic constants the deck gave (closed-form references of verification decks read them).
  virtual const ElasticConstants& elastic_constants() const = 0;
  // What the law derived from its keys, for a comment beside the printed map.
  virtual std::string derived_values() const = 0;
};

// The same calls on F or H, as free functions (element routines, tests).
inline StressResult stress_from_displacement_gradient(const MaterialLaw& law, const Mat3& H,
                                                      bool with_tangent) {
  return law.stress(H, with_tangent);
}
inline StressResult stress(const MaterialLaw& law, const Mat3& F, bool with_tangent = true) {
  return law.stress(F - Mat3::Identity(), with_tangent);
}
inline Mat3 cauchy_stress(const MaterialLaw& law, const Mat3& F) { return law.cauchy_stress(F); }

// Von Mises equivalent stress sqrt(3/2 dev(sigma) : dev(sigma)).
double von_mises(const Mat3& sigma);

// The result of a finite-strain law at det F <= 0 (or outside its domain): psi = +inf,
// P = A = NaN.
StressResult inverted_result();

}  // namespace hs
