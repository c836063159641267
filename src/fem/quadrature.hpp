// Quadrature rules on the reference tetrahedron {xi >= 0, xi_0 + xi_1 + xi_2 <= 1} (volume
// 1/6) and the reference triangle {xi >= 0, xi_0 + xi_1 <= 1} (area 1/2).
//
// Degree 1 and 2 use the classical symmetric 1- and 4-point (tetrahedron) / 1- and 3-point
// (triangle) rules. Higher degrees use the collapsed Gauss-Jacobi product rule: the cube
// (u, v, w) in [0,1]^3 maps onto the tetrahedron by
//   xi_0 = u,  xi_1 = (1 - u) v,  xi_2 = (1 - u)(1 - v) w,  dxi = (1 - u)^2 (1 - v) du dv dw,
// and n-point Gauss-Jacobi rules for the weights (1 - u)^2, (1 - v)^1, (1 - w)^0 integrate
// the image of any polynomial of total degree <= 2n - 1 exactly (the triangle likewise with
// (1 - u)^1, (1 - v)^0).
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace hs {

struct TetQuadrature {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;  // sum to 1/6
};

struct TriQuadrature {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> weights;  // sum to 1/2
};

constexpr int kMaxQuadratureDegree = 15;

// Rules exact for polynomials of total degree <= degree (0 <= degree <= kMaxQuadratureDegree;
// else std::invalid_argument). Built once; the references stay valid for the program's life.
const TetQuadrature& tet_quadrature(int degree);
const TriQuadrature& tri_quadrature(int degree);

// n-point Gauss-Jacobi rule on [0, 1] for the weight (1 - x)^alpha (Golub-Welsch): exact for
// int_0^1 (1 - x)^alpha p(x) dx with p of degree <= 2n - 1.
void gauss_jacobi(int n, int alpha, std::vector<double>& points, std::vector<double>& weights);

}  // namespace hs
