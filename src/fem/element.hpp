// Element routines of the total-Lagrangian displacement formulation on P1/P2 tetrahedra.
// One routine computes the residual and the tangent of an element, so the two can never
// disagree (tested against finite differences in tests/fem).
//
// Arrays are node-major: X[3*a + i] is coordinate i of element node a; the same for u, r.
// Matrices are row-major (3*npe) x (3*npe): K[(3a+i)*(3*npe) + 3b+j] = d r_{3a+i} / d u_{3b+j}.
#pragma once

#include <array>
#include <functional>

#include "materials/material.hpp"

namespace hs {

// The quadrature degrees of the element routines (element.cpp says why these): what the
// mesh checks sample a curved element's Jacobian at (src/mesh/mesh_checks.cpp).
struct QuadratureDegrees {
  int stiffness, volume, body, mass;
};
constexpr QuadratureDegrees kP1Degrees{1, 1, 1, 2};
constexpr QuadratureDegrees kP2Degrees{2, 3, 5, 7};

struct ElementOutput {
  bool valid = true;  // false if any quadrature point has det F <= 0 (inverted element);
                      // linear_elastic, a small-strain law, is never inverted
  double energy = 0;  // integral of psi over the element
};

// Internal force r = int P : grad N dV and its tangent K = dr/du (K may be nullptr).
ElementOutput tet_internal_force(int order, const double* X, const double* u, const MaterialLaw& m,
                                 double* r, double* K);

// A P1 element's reference geometry, which no configuration changes: grad N_a (column a of
// a 3 x 4 column-major array) and the volume. Kept per element by the assembly, it spares
// tet_internal_force_p1 the reference Jacobian and its inverse at every call.
struct P1Geometry {
  double grad[12];
  double volume;
};
P1Geometry tet_p1_geometry(const double* X);  // throws InputError as tet_internal_force

// tet_internal_force(1, X, ...) from the element's P1Geometry (the same numbers).
ElementOutput tet_internal_force_p1(const P1Geometry& g, const double* u, const MaterialLaw& m,
                                    double* r, double* K);

// The change v - V of a P1 element's volume at displacements u, and (where not nullptr) its
// gradient dv/du (12 values) and Hessian d2v/du2 (12 x 12, row-major): what the nodal-pressure
// element of P1 meshes assembles (src/fem/p1_volume.cpp). v - V keeps the digits of a small
// change (V det_minus_one(H)). linearised: the first-order change V tr(H), its gradient, a zero
// Hessian (the volume change of a small-strain law).
double p1_volume_change(const P1Geometry& g, const double* u, double* grad, double* hess,
                        bool linearised = false);

// The F-bar element of nearly incompressible bodies (src/fem/fbar_element.cpp): the law at
// Fbar = (Jbar/J)^(1/3) F, Jbar the element's volume ratio, so that a P2 element carries one
// volumetric constraint instead of four and does not lock. Same outputs as tet_internal_force
// (on a P1 element the two are equal).
ElementOutput tet_internal_force_fbar(int order, const double* X, const double* u,
                                      const MaterialLaw& m, double* r, double* K);

// Newton's own pressure in an F-bar element's tangent (docs/formulation.md): the law split
// into `rest` (the law less its volumetric term, WithoutVolumetricTerm) at Fbar and the term
// k/2 (ln Jbar)^2 on the element's volume ratio, the residual exact, and in the tangent the
// Kirchhoff pressure q in place of k ln Jbar(u): V [(k - q) / Jbar^2 b b^T + q / Jbar
// d2Jbar/du2] for the term's V k [(1 - ln Jbar) / Jbar^2 b b^T + ln Jbar / Jbar d2Jbar/du2],
// b = dJbar/du. Newton's q is k (ln Jbar(u0) + b(u0) . (u - u0) / Jbar(u0)), u0 the previous
// tangent's point; the kernel returns ln Jbar and b / Jbar at u for the next one.
// An exactly incompressible element (nu = 0.5) adds its volume multiplier's V lambda ln Jbar
// (solvers/incompressibility.hpp): lambda joins both pressures.
struct FbarNewtonPressure {
  const MaterialLaw* rest = nullptr;
  double k = 0;
  double lambda = 0;  // the element's volume multiplier
  bool exact = true;  // q = k ln Jbar(u): the exact tangent (the first, or after an inversion)
  double q = 0;
  double ln_Jbar = 0;  // out
  double g[30] = {};   // out: b / Jbar, 3 per node
};
ElementOutput tet_internal_force_fbar(int order, const double* X, const double* u,
                                      FbarNewtonPressure& p, double* r, double* K);
// Jbar - 1 of an F-bar element (finite strain), by the same rule and arithmetic as its forces.
double tet_volume_ratio_minus_one_fbar(int order, const double* X, const double* u);

// Consistent nodal body force f_a = int rho g N_a dV (reference configuration).
void tet_body_force(int order, const double* X, double rho, const std::array<double, 3>& g,
                    double* f);
// The same for a force per unit reference volume that varies in space (a manufactured
// solution's), integrated by a rule of degree 2 order + 4.
using ForceDensity = std::function<std::array<double, 3>(const std::array<double, 3>& X)>;
void tet_body_force(int order, const double* X, const ForceDensity& density, double* f);

// Consistent mass matrix M_ab = int rho N_a N_b dV, returned as (3 npe)^2 with 3x3 identity blocks.
void tet_mass(int order, const double* X, double rho, double* M);

// Reference volume of the element.
double tet_volume(int order, const double* X);

// Follower pressure p on a triangle face (3 or 6 nodes) of the current configuration
// x = X + u, the face's right-hand normal pointing out of the body. The nodal forces are
//   f_a = -p int N_a n da
// (a positive p pushes into the body). Returns f in f[3*npf] and, if K is not nullptr,
// K = df/dx (the load stiffness, not symmetric in general).
void face_pressure(int order, const double* x, double p, double* f, double* K);

// A dead traction t (force per reference area, fixed in direction and size) on a triangle face
// (3 or 6 nodes) of the reference configuration X: f_a = t int N_a dA. Exact on flat faces.
void face_traction(int order, const double* X, const std::array<double, 3>& t, double* f);

// A face's share of the volume enclosed by a closed surface whose faces point out of the body
// (a cavity): V = -1/3 int x . n da, exact for Tri3 and Tri6. Summed over a closed surface,
// the gradient of V in the nodal positions is face_pressure's force at p = 1 (the pressure
// term J_p^T of the paper) and its Hessian that force's load stiffness; on one face they
// differ (terms on its edges, which cancel between neighbours).
double face_enclosed_volume(int order, const double* x);

// det F at the element centroid > 0 (and finite), from positions alone: det F is
// det(dx/dxi) / det(dX/dxi), and det(dX/dxi) > 0 on every accepted mesh, so only the sign
// of the deformed Jacobian is needed. For the laws here a finite u with det F > 0 gives a
// finite stress, so this is the inversion check of a step at a tenth of tet_fields' cost.
bool tet_orientation_preserved(int order, const double* X, const double* u);

// Element values for output, at the element centroid: the Cauchy stress sigma (Pa), its von
// Mises value, the Green-Lagrange strain E = (F^T F - I) / 2 and J = det F.
struct ElementFields {
  double von_mises = 0;
  double J = 1;
  Mat3 stress = Mat3::Zero();
  Mat3 strain = Mat3::Zero();
};
// E = (H + H^T + H^T H) / 2 from H = F - I, which keeps a small strain's relative precision.
Mat3 green_lagrange_strain(const Mat3& H);
// The eigenvalues of a symmetric tensor, largest first (principal stresses or strains).
std::array<double, 3> principal_values(const Mat3& symmetric);
ElementFields tet_fields(int order, const double* X, const double* u, const MaterialLaw& m);
// The same for the F-bar element: the stress and the strain at Fbar, J = Jbar.
ElementFields tet_fields_fbar(int order, const double* X, const double* u, const MaterialLaw& m);

}  // namespace hs
