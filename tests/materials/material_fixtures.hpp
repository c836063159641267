// Shared by the material tests: one law of each kind built from its class with the same
// small-strain constants, random deformation gradients, finite differences of psi and P.
#pragma once

#include <map>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "materials/corotational.hpp"
#include "materials/gent.hpp"
#include "materials/linear_elastic.hpp"
#include "materials/mooney_rivlin.hpp"
#include "materials/neo_hookean.hpp"
#include "materials/registry.hpp"
#include "materials/saint_venant_kirchhoff.hpp"
#include "materials/yeoh.hpp"

namespace hs::material_fixtures {

const double kMu = 3.0, kLambda = 7.0;  // E = 7.8, nu = 0.35
// Gent's limit of I1b - 3: the random gradients below reach I1b - 3 ~ 3, well into stiffening.
const double kJm = 10.0;
// Yeoh's C2, C3 (C1 = mu / 2): C2 < 0 as in published fits, both terms of the order of the first
// at I1b - 3 ~ 3; dpsi/dI1b stays positive (C2^2 < 3 C1 C3).
const double kC2 = -0.05 * kMu, kC3 = 0.02 * kMu;

// Each law with the small-strain constants c (Mooney-Rivlin: c1 + c2 = mu / 2, Yeoh: C1 =
// mu / 2), the other parameters in proportion to mu. A law of the registry missing here fails
// every test that iterates the registry's laws (its name is not a key of this map).
inline std::shared_ptr<const MaterialLaw> make_law(const std::string& name,
                                                   const ElasticConstants& c) {
  using Make = std::shared_ptr<const MaterialLaw> (*)(const ElasticConstants&);
  static const std::map<std::string, Make> makers = {
      {"linear_elastic",
       [](const ElasticConstants& c) -> std::shared_ptr<const MaterialLaw> {
         return std::make_shared<LinearElasticLaw>(c);
       }},
      {"corotational",
       [](const ElasticConstants& c) -> std::shared_ptr<const MaterialLaw> {
         return std::make_shared<CorotationalLaw>(c);
       }},
      {"saint_venant_kirchhoff",
       [](const ElasticConstants& c) -> std::shared_ptr<const MaterialLaw> {
         return std::make_shared<SaintVenantKirchhoffLaw>(c);
       }},
      {"neo_hookean",
       [](const ElasticConstants& c) -> std::shared_ptr<const MaterialLaw> {
         return std::make_shared<NeoHookeanLaw>(c);
       }},
      {"mooney_rivlin",
       [](const ElasticConstants& c) -> std::shared_ptr<const MaterialLaw> {
         return std::make_shared<MooneyRivlinLaw>(c, 0.3 * c.mu, 0.2 * c.mu);
       }},
      {"gent",
       [](const ElasticConstants& c) -> std::shared_ptr<const MaterialLaw> {
         return std::make_shared<GentLaw>(c, kJm);
       }},
      {"yeoh",
       [](const ElasticConstants& c) -> std::shared_ptr<const MaterialLaw> {
         return std::make_shared<YeohLaw>(c, kC2 / kMu * c.mu, kC3 / kMu * c.mu);
       }},
  };
  const auto maker = makers.find(name);
  if (maker == makers.end())
    throw std::invalid_argument("no test law '" + name + "' in material_fixtures.hpp");
  return maker->second(c);
}

// The registry's laws, in its order.
inline std::vector<std::string> all_law_names() { return material_law_names(); }
// Every law of the registry with mu = kMu, lambda = kLambda.
inline const std::map<std::string, std::shared_ptr<const MaterialLaw>>& all_laws() {
  static const std::map<std::string, std::shared_ptr<const MaterialLaw>> laws = [] {
    std::map<std::string, std::shared_ptr<const MaterialLaw>> laws;
    for (const std::string& name : all_law_names())
      laws[name] = make_law(name, elastic_constants_from_lame(kMu, kLambda));
    return laws;
  }();
  return laws;
}

inline const MaterialLaw& law(const std::string& name) { return *all_laws().at(name); }

// The registry's laws but the small-strain (linear) ones. A law without its test law is kept,
// so that its tests fail with make_law's message rather than the executable at its start.
inline std::vector<std::string> finite_strain_law_names() {
  std::vector<std::string> names;
  for (const std::string& name : all_law_names()) {
    bool linear = false;
    try {
      linear = law(name).tangent_always_definite();
    } catch (const std::invalid_argument&) {
    }
    if (!linear) names.push_back(name);
  }
  return names;
}

inline Mat3 rotation(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

// Random rotation from a random axis and angle in [-pi, pi].
inline Mat3 random_rotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  return rotation(Eigen::Vector3d(d(rng), d(rng), d(rng)), M_PI * d(rng));
}

// F = I + amplitude * (random matrix); redrawn until det F >= 0.3 (large amplitudes).
inline Mat3 random_F(std::mt19937& rng, double amplitude) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  for (;;) {
    Mat3 H;
    for (int i = 0; i < 9; ++i) H(i) = d(rng);
    const Mat3 F = Mat3::Identity() + amplitude * H;
    if (F.determinant() >= 0.3) return F;
  }
}

inline double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& reference) {
  return (a - reference).norm() / reference.norm();
}

// Central differences of psi in each F_kl (row-major flattening as the tangent).
inline Mat3 fd_stress(const MaterialLaw& m, const Mat3& F, double h) {
  Mat3 P;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      Mat3 Fp = F, Fm = F;
      Fp(k, l) += h;
      Fm(k, l) -= h;
      P(k, l) = (stress(m, Fp).psi - stress(m, Fm).psi) / (2 * h);
    }
  return P;
}

inline Tangent fd_tangent(const MaterialLaw& m, const Mat3& F, double h) {
  Tangent A;
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) {
      Mat3 Fp = F, Fm = F;
      Fp(k, l) += h;
      Fm(k, l) -= h;
      const Mat3 dP = (stress(m, Fp).P - stress(m, Fm).P) / (2 * h);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) A(3 * i + j, 3 * k + l) = dP(i, j);
    }
  return A;
}

}  // namespace hs::material_fixtures
