// ||u_h - u||_L2 over the reference domain, element by element:
//   sum_e sum_q w_q |det J_e(xi_q)| |u_h(xi_q) - u(X(xi_q))|^2,
// with an isoparametric map X(xi) = sum_a N_a(xi) X_a (curved P2 elements included) and a
// rule of degree 2 (order + 1), enough to integrate |u_h|^2 exactly on straight elements.
#include "solvers/verification/error_norms.hpp"

#include <Eigen/Dense>
#include <cmath>

#include "fem/quadrature.hpp"
#include "fem/shape.hpp"

namespace hs {

ErrorNorms displacement_error(const Problem& problem, Vec u, const ExactSolution& exact, double s) {
  const Distribution& dist = problem.distribution();
  const int order = dist.order, npe = dist.nodes_per_tet();
  const TetQuadrature& rule = tet_quadrature(2 * (order + 1));

  // The displacement of the local (owned + ghost) nodes.
  VecHandle uw;
  HS_PETSC(VecDuplicate(u, uw.out()));
  double err2 = 0, norm2 = 0;
  {
    const Problem::LocalView view(u, uw);
    const PetscScalar* ua = view.values();
    double N[10], dN[30];
    for (size_t e = 0; e < dist.local_tets.size(); ++e) {
      const int32_t* nodes = &dist.tet_nodes[e * npe];
      for (size_t q = 0; q < rule.points.size(); ++q) {
        tet_shape(order, rule.points[q], N, dN);
        Eigen::Vector3d X = Eigen::Vector3d::Zero(), uh = Eigen::Vector3d::Zero();
        Eigen::Matrix3d J = Eigen::Matrix3d::Zero();  // dX/dxi
        for (int a = 0; a < npe; ++a) {
          const Eigen::Vector3d Xa(problem.reference_coordinate(nodes[a], 0),
                                   problem.reference_coordinate(nodes[a], 1),
                                   problem.reference_coordinate(nodes[a], 2));
          X += N[a] * Xa;
          uh +=
              N[a] * Eigen::Vector3d(ua[3 * nodes[a]], ua[3 * nodes[a] + 1], ua[3 * nodes[a] + 2]);
          J += Xa * Eigen::RowVector3d(dN[3 * a], dN[3 * a + 1], dN[3 * a + 2]);
        }
        const auto ue = exact.displacement({X[0], X[1], X[2]}, s);
        const Eigen::Vector3d uex(ue[0], ue[1], ue[2]);
        const double w = rule.weights[q] * std::abs(J.determinant());
        err2 += w * (uh - uex).squaredNorm();
        norm2 += w * uex.squaredNorm();
      }
    }
  }

  double local[2] = {err2, norm2}, global[2] = {0, 0};
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_SUM, problem.comm());
  ErrorNorms r;
  r.l2_absolute = std::sqrt(global[0]);
  r.l2_relative = global[1] > 0 ? std::sqrt(global[0] / global[1]) : r.l2_absolute;
  return r;
}

namespace {

// sum over the local elements and the rule's points of w |det J| f(e, X), over all ranks.
template <class F>
double integrate(const Problem& problem, const TetQuadrature& rule, F f) {
  const Distribution& dist = problem.distribution();
  const int order = dist.order, npe = dist.nodes_per_tet();
  double N[10], dN[30], sum = 0;
  for (size_t e = 0; e < dist.local_tets.size(); ++e) {
    const int32_t* nodes = &dist.tet_nodes[e * npe];
    for (size_t q = 0; q < rule.points.size(); ++q) {
      tet_shape(order, rule.points[q], N, dN);
      Eigen::Vector3d X = Eigen::Vector3d::Zero();
      Eigen::Matrix3d J = Eigen::Matrix3d::Zero();
      for (int a = 0; a < npe; ++a) {
        const Eigen::Vector3d Xa(problem.reference_coordinate(nodes[a], 0),
                                 problem.reference_coordinate(nodes[a], 1),
                                 problem.reference_coordinate(nodes[a], 2));
        X += N[a] * Xa;
        J += Xa * Eigen::RowVector3d(dN[3 * a], dN[3 * a + 1], dN[3 * a + 2]);
      }
      sum += rule.weights[q] * std::abs(J.determinant()) *
             f(e, std::array<double, 3>{X[0], X[1], X[2]});
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_DOUBLE, MPI_SUM, problem.comm());
  return sum;
}

}  // namespace

ErrorNorms pressure_error(const Problem& problem, Vec u, const ExactSolution& exact) {
  Problem::ElementFieldValues fields;
  problem.element_fields(u, fields, false);
  const auto ph = [&](size_t e) {
    const double* S = &fields.stress[9 * e];
    return -(S[0] + S[4] + S[8]) / 3;
  };
  const TetQuadrature& rule = tet_quadrature(2 * (problem.distribution().order + 1));
  const double err2 = integrate(problem, rule, [&](size_t e, const std::array<double, 3>& X) {
    return std::pow(ph(e) - exact.pressure(X), 2);
  });
  const double norm2 = integrate(problem, rule, [&](size_t, const std::array<double, 3>& X) {
    return std::pow(exact.pressure(X), 2);
  });
  ErrorNorms r;
  r.l2_absolute = std::sqrt(err2);
  r.l2_relative = norm2 > 0 ? std::sqrt(err2 / norm2) : r.l2_absolute;
  return r;
}

}  // namespace hs
