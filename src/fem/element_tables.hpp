// Shape function values and reference gradients at the points of a quadrature rule, computed
// once per (element type, degree) so that element routines only do the geometry and the
// physics. Internal to src/fem.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "fem/quadrature.hpp"
#include "fem/shape.hpp"

namespace hs {

// NPE = 4 / 10: Tet4 / Tet10; NPE = 3 / 6: Tri3 / Tri6 (DIM = 3 or 2 reference coordinates).
template <int NPE, int DIM>
struct ShapeTables {
  std::vector<double> weights;
  std::vector<Eigen::Matrix<double, NPE, 1>> N;
  std::vector<Eigen::Matrix<double, DIM, NPE>> dN;  // dN(d, a) = dN_a / dxi_d
};

template <int NPE>
using TetTables = ShapeTables<NPE, 3>;
template <int NPF>
using TriTables = ShapeTables<NPF, 2>;

namespace detail {

template <int NPE, int DIM, class Rule, class ShapeFn>
ShapeTables<NPE, DIM> make_tables(const Rule& rule, ShapeFn shape) {
  ShapeTables<NPE, DIM> t;
  t.weights = rule.weights;
  for (const auto& xi : rule.points) {
    Eigen::Matrix<double, NPE, 1> N;
    Eigen::Matrix<double, DIM, NPE> dN;  // column-major: dN.data()[DIM a + d]
    shape(xi, N.data(), dN.data());
    t.N.push_back(N);
    t.dN.push_back(dN);
  }
  return t;
}

}  // namespace detail

// Tables of the P1 (NPE = 4) or P2 (NPE = 10) tetrahedron on tet_quadrature(degree).
template <int NPE>
const TetTables<NPE>& tet_tables(int degree) {
  static_assert(NPE == 4 || NPE == 10, "Tet4 or Tet10");
  static const std::vector<TetTables<NPE>> all = [] {
    std::vector<TetTables<NPE>> v;
    for (int d = 0; d <= kMaxQuadratureDegree; ++d)
      v.push_back(detail::make_tables<NPE, 3>(tet_quadrature(d),
                                              [](const Eigen::Vector3d& xi, double* N, double* dN) {
                                                tet_shape(NPE == 4 ? 1 : 2, xi, N, dN);
                                              }));
    return v;
  }();
  return all.at(degree);
}

// Tables of the P1 (NPF = 3) or P2 (NPF = 6) triangle on tri_quadrature(degree).
template <int NPF>
const TriTables<NPF>& tri_tables(int degree) {
  static_assert(NPF == 3 || NPF == 6, "Tri3 or Tri6");
  static const std::vector<TriTables<NPF>> all = [] {
    std::vector<TriTables<NPF>> v;
    for (int d = 0; d <= kMaxQuadratureDegree; ++d)
      v.push_back(detail::make_tables<NPF, 2>(tri_quadrature(d),
                                              [](const Eigen::Vector2d& xi, double* N, double* dN) {
                                                tri_shape(NPF == 3 ? 1 : 2, xi, N, dN);
                                              }));
    return v;
  }();
  return all.at(degree);
}

}  // namespace hs
