// The controller's step 3 with the contact forces among the unknowns (control.contact_forces:
// qp; docs/control.md, "Contact forces in the QP"): beside the actuation changes dl, the
// normal force lambda_c >= 0 of each candidate contact node c, under complementarity with its
// gap,
//   g_c = g0_c + G_ca dl + G_cc dlambda >= 0,   lambda_c >= 0,   lambda_c g_c = 0,
// the gaps linear through the compliance (G: the normal move of a node per unit actuation and
// per unit normal force). A mathematical program with complementarity constraints, solved by
// active sets (principal pivoting): for a guess A of the touching nodes, the forces of A are
// those that close their gaps (G_AA dlambda_A = -g_A: affine in dl), the others' are zero, so
// that every quantity is affine in dl and the QP of control/actuation_qp.hpp is solved over
// dl alone; then a node of A whose force came out negative leaves A and one outside whose gap
// closed joins it, until no node changes. With the actuation held this is the contact LCP,
// whose G_cc is positive definite: principal pivoting by the least-index rule ends there.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "control/actuation_qp.hpp"

namespace hs {

struct ContactBlocks {
  Eigen::MatrixXd G_cc;  // N x N: normal move of candidate i per unit normal force on j (m/N)
  Eigen::MatrixXd G_ca;  // N x n: normal move of candidate i per unit actuation
  Eigen::VectorXd gap;   // the candidates' gaps at the free configuration (m)
  Eigen::VectorXd held;  // the candidates' normal forces there (N, >= 0)
  // The effectors' weighted rows over dl (r x n) and over the force changes (r x N), and
  // their weighted distance to the targets (as solve_actuation_qp's W and delta). A force
  // effector's row over the forces is minus the normals' component on its own candidates.
  Eigen::MatrixXd W_a, W_c;
  Eigen::VectorXd delta;
  // A force effector none of whose candidates touches closes the gap of its nearest one
  // instead, as a spring across it that gives the force asked when the gap closes: per row,
  // that candidate (-1: a position row, or a force row without candidates) and the spring's
  // row factor (weight x asked force / gap x the normal's component along the row).
  std::vector<int> approach;
  Eigen::VectorXd approach_factor;
  // Each actuator's measure change per unit actuation (n x n) and per unit force (n x N).
  Eigen::MatrixXd growth_a, growth_c;
  double gap_tolerance = 0;  // a gap at most this is closed (m)
};

struct ContactActuation {
  ActuationChange change;    // dl and the QP's report for the final active set
  Eigen::VectorXd dforce;    // the candidates' force changes (N; zero when not solved)
  int passes = 0;            // active sets tried
  int touching = 0;          // nodes in the final active set
  bool cycled = false;       // the sets did not settle (the last one's answer is kept)
  double worst_product = 0;  // max over c of |lambda_c g_c| at the answer (N m)
  double least_gap = 0;      // the smallest linearised gap at the answer (m)
  double least_force = 0;    // the smallest force at the answer (N)
};

ContactActuation solve_contact_actuation_qp(const ContactBlocks& blocks,
                                            const std::vector<ActuatorConfig>& bounds,
                                            const std::vector<ActuatorPosition>& at,
                                            double regularization);

}  // namespace hs
