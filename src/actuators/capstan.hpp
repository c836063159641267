// The forces of a cable with Coulomb friction where it turns (the capstan equation), as a pure
// function of its path: points p_0 .. p_n, segments k = 0 .. n-1 from p_k to p_{k+1}, the last
// one ending at the motor that pulls with tension T. Where the cable turns at an interior
// point j by the angle theta_j (between segments j-1 and j) and slides towards the motor, the
// tension falls away from the motor by exp(-mu theta_j), so segment k carries
//   T_k = T tau_k,  tau_k = exp(-mu sum_{j=k+1}^{n-1} theta_j)   (tau_{n-1} = 1),
// and puts T_k e_k on p_k and -T_k e_k on p_{k+1} (e_k its unit vector): the force on point i
// per unit motor tension is
//   F_i = tau_i e_i - tau_{i-1} e_{i-1}   (terms of segments that do not exist left out).
// With mu = 0 every tau is 1 and F = -dL/dp, the frictionless cable. With mu > 0 the forces are
// no gradient: their Jacobian dF/dp is not symmetric. Derivation in docs/formulation.md,
// "Cable with capstan friction".
#pragma once

#include <array>
#include <vector>

namespace hs {

struct CapstanForces {
  std::vector<std::array<double, 3>> force;  // F_i per unit motor tension, one per point
  std::vector<double> tension;               // tau_k, one per segment
  // dF_i/dp_m, (3 (n+1))^2 entries, row-major over (3 i + a, 3 m + b); empty unless asked.
  std::vector<double> jacobian;
};

// Requires at least two points and segments of positive length; mu >= 0. At a straight
// interior point (theta = 0, where theta is not differentiable) the derivative of theta is
// taken as zero.
CapstanForces capstan_forces(const std::vector<std::array<double, 3>>& p, double mu,
                             bool with_jacobian);

}  // namespace hs
