// Pointwise constitutive laws: first Piola-Kirchhoff stress P(F) and its tangent dP/dF.
// Pure functions of the deformation gradient and the parameters, so that each can be
// checked against finite differences (tests/materials).
#pragma once

#include <Eigen/Dense>
#include <string>

namespace hs {

using Mat3 = Eigen::Matrix3d;
// dP_ij / dF_kl stored at (3*i + j, 3*k + l) (row-major flattening of both).
using Tangent = Eigen::Matrix<double, 9, 9>;

enum class MaterialModel {
  LinearElastic,
  Corotational,
  SaintVenantKirchhoff,
  NeoHookean,
  MooneyRivlin
};

struct MaterialParameters {
  MaterialModel model = MaterialModel::LinearElastic;
  double mu = 0, lambda = 0;  // Lame parameters
  double c1 = 0, c2 = 0;      // Mooney-Rivlin
  double density = 0;
};

// Throws std::invalid_argument for an unknown name.
MaterialModel material_model_from_name(const std::string& name);
std::string material_model_name(MaterialModel model);

struct StressResult {
  Mat3 P;      // first Piola-Kirchhoff stress
  Tangent A;   // dP/dF
  double psi;  // strain energy density (where the model has one)
};

// Stress, tangent and energy density at one point. For det F <= 0 the finite-strain
// models return a non-finite psi; callers must treat that as an inverted element.
StressResult stress(const MaterialParameters& m, const Mat3& F);
// The same; with_tangent = false skips computing A (residual-only evaluations).
StressResult stress(const MaterialParameters& m, const Mat3& F, bool with_tangent);
// The same from the displacement gradient H = F - I, which element routines have: small
// strains keep their relative precision (F - I would leave an absolute error of 1e-16, i.e.
// a stress error of 1e-16 times the stiffness, a residual floor for small loads).
StressResult stress_from_displacement_gradient(const MaterialParameters& m, const Mat3& H,
                                               bool with_tangent);

// Cauchy stress sigma = P F^T / J, used for output (von Mises).
// For linear_elastic (small strain) it is P itself.
Mat3 cauchy_stress(const MaterialParameters& m, const Mat3& F);

// Von Mises equivalent stress sqrt(3/2 dev(sigma) : dev(sigma)).
double von_mises(const Mat3& sigma);

}  // namespace hs
