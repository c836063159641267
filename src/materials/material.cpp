#include "materials/material.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "materials/models.hpp"

namespace hs {
namespace {

struct ModelName {
  MaterialModel model;
  const char* name;
};
constexpr ModelName kModelNames[] = {
    {MaterialModel::LinearElastic, "linear_elastic"},
    {MaterialModel::Corotational, "corotational"},
    {MaterialModel::SaintVenantKirchhoff, "saint_venant_kirchhoff"},
    {MaterialModel::NeoHookean, "neo_hookean"},
    {MaterialModel::MooneyRivlin, "mooney_rivlin"},
};

}  // namespace

MaterialModel material_model_from_name(const std::string& name) {
  std::string known;
  for (const auto& m : kModelNames) {
    if (name == m.name) return m.model;
    known += known.empty() ? m.name : std::string(", ") + m.name;
  }
  throw std::invalid_argument("unknown material model '" + name + "' (known: " + known + ")");
}

std::string material_model_name(MaterialModel model) {
  for (const auto& m : kModelNames)
    if (model == m.model) return m.name;
  throw std::invalid_argument("unknown material model " + std::to_string(static_cast<int>(model)));
}

StressResult inverted_result() {
  StressResult s;
  s.P.setConstant(std::numeric_limits<double>::quiet_NaN());
  s.A.setConstant(std::numeric_limits<double>::quiet_NaN());
  s.psi = std::numeric_limits<double>::infinity();
  return s;
}

StressResult stress_from_displacement_gradient(const MaterialParameters& m, const Mat3& H,
                                               bool with_tangent) {
  switch (m.model) {
    case MaterialModel::LinearElastic:
      return linear_elastic(m.mu, m.lambda, H, with_tangent);
    case MaterialModel::Corotational:
      return corotational(m.mu, m.lambda, H, with_tangent);
    case MaterialModel::SaintVenantKirchhoff:
      return saint_venant_kirchhoff(m.mu, m.lambda, H, with_tangent);
    case MaterialModel::NeoHookean:
      return neo_hookean(m.mu, m.lambda, H, with_tangent);
    case MaterialModel::MooneyRivlin:
      // Bulk modulus of the small-strain limit; the shear modulus there is 2 (c1 + c2).
      return mooney_rivlin(m.c1, m.c2, m.lambda + 2.0 * m.mu / 3.0, H, with_tangent);
  }
  throw std::invalid_argument("unknown material model " +
                              std::to_string(static_cast<int>(m.model)));
}

StressResult stress(const MaterialParameters& m, const Mat3& F, bool with_tangent) {
  return stress_from_displacement_gradient(m, F - Mat3::Identity(), with_tangent);
}

StressResult stress(const MaterialParameters& m, const Mat3& F) { return stress(m, F, true); }

Mat3 cauchy_stress(const MaterialParameters& m, const Mat3& F) {
  const Mat3 P = stress(m, F, false).P;
  // Small strain does not tell the configurations apart: its P already is sigma.
  if (m.model == MaterialModel::LinearElastic) return P;
  return P * F.transpose() / F.determinant();
}

double von_mises(const Mat3& sigma) {
  const Mat3 s = sigma - sigma.trace() / 3.0 * Mat3::Identity();
  return std::sqrt(1.5 * s.squaredNorm());
}

}  // namespace hs
