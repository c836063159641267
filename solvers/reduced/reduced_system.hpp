// A reduced-order model on a run's problem (docs/reduced_models.md): the displacements
// u = Phi q in the span of the model's POD basis Phi (k columns), and equation (1) of the paper
// projected on it,
//   r(q) = sum_{e in E} w_e Phi_e^T f_e(Phi_e q) - Phi^T f_dead - Phi^T f_c(Phi q, lambda) = 0,
// the internal forces hyper-reduced (ECSW: the sampled elements E and their weights w; a
// nodal-pressure body's volumetric term by sampled node patches and their weights), the
// obstacles' barrier at every contact node,
// dead loads (gravity, tractions) projected once, and the constraints' forces f_c (the
// cavities' pressures on their walls, the liquid's weight, the cables' tensions) evaluated by
// the constraints themselves on the walls of the reconstructed body. Only the sampled dofs of u
// are kept up to date (the sampled elements' nodes, the constraints' and the effectors'):
// a reduced evaluation never touches the rest of the mesh. One rank.
#pragma once

#include <petscvec.h>

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "reduction/model_file.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/problem.hpp"

namespace hs {

struct ReducedSolve {
  bool converged = false;
  int iterations = 0;
  double residual = 0;  // |r| / its scale at the end
  std::string reason;
};

// The reduced equations linearized at q and the constraints' multipliers lambda:
// r + K dq - G dlambda = 0 to first order.
struct ReducedLinearization {
  Eigen::VectorXd r;  // r(q)
  Eigen::MatrixXd K;  // dr/dq
  Eigen::MatrixXd G;  // Phi^T g_c, each constraint's unit forces (a column each)
  double scale = 1;   // the forces r balances (N)
};

// A vector's local values (one rank: every dof), copied.
Eigen::VectorXd local_values(Vec v);

class ReducedSystem {
 public:
  // Throws InputError naming `path` when the model does not belong to the run: another mesh
  // (nodes, tetrahedra, order, coordinates), other physics, other actuators, a body this
  // formulation cannot reduce (the nodal-pressure element, a deck's follower pressure load),
  // more than one rank. `rows`: vectors whose support must be kept up to date too (the
  // effectors' rows).
  ReducedSystem(const Config& config, Problem& problem, ConstraintSet& constraints,
                const ReducedModel& model, const std::string& path, const std::vector<Vec>& rows);

  int size() const { return static_cast<int>(phi_.cols()); }
  Eigen::Index dofs() const { return phi_.rows(); }  // the full model's (local: all)
  int sampled_dofs() const { return static_cast<int>(sample_.size()); }
  // q = Phi^T u (Phi's columns are orthonormal).
  Eigen::VectorXd project(Vec u) const;
  // r^T Phi for a vector r (an effector's row).
  Eigen::RowVectorXd project_row(Vec r) const;
  // u <- Phi q at the sampled dofs (every dof with `everywhere`).
  void place(const Eigen::VectorXd& q, Vec u, bool everywhere) const;
  // Newton in the reduced space at the constraints' current multipliers, from q (updated in
  // place); u follows at the sampled dofs.
  ReducedSolve solve(Eigen::VectorXd& q, Vec u);
  // Newton at the actuation `lambda` (the model's actuators, in order) from the nearest
  // training sample into q; where that fails, the actuation is stepped from the sample's to
  // lambda in 2, then 4, then 8 equal parts: near a limit point of the actuation the reduced
  // Newton, like the full one, converges slowly from afar. The actuators are left at lambda,
  // or at the last part tried where every attempt fails.
  ReducedSolve solve_at(const Eigen::VectorXd& lambda, Eigen::VectorXd& q, Vec u);
  // The equations linearized at q (false outside the domain). Leaves u at q. The elements'
  // part of K is exact; the constraints' part (the walls' follower stiffness) comes, with
  // `fresh`, from k evaluations of their forces and otherwise from the last such evaluation
  // corrected by the secant of the last two linearizations (Broyden's update).
  bool linearize(const Eigen::VectorXd& q, Vec u, ReducedLinearization& L, bool fresh);
  // Whether r balances to Newton's tolerance (the column method's jump as its floor).
  bool balanced(const ReducedLinearization& L) const;
  // The reduced coordinates of the training sample nearest to the actuation `lambda` (the
  // model's actuators; each one's distance scaled by its training range): where a solve far
  // from the last equilibrium starts.
  Eigen::VectorXd nearest_training_state(const Eigen::VectorXd& lambda) const {
    return training_states_.row(nearest_training_sample(lambda)).transpose();
  }
  Eigen::Index nearest_training_sample(const Eigen::VectorXd& lambda) const;
  // The training samples: actuations (one row each) and reduced coordinates.
  const Eigen::MatrixXd& training_actuations() const { return training_actuations_; }
  const Eigen::MatrixXd& training_states() const { return training_states_; }
  // The size of the forces r balances (N): |Phi^T f_dead| and the constraints' at the last
  // evaluation.
  double force_scale() const { return force_scale_; }
  // |r(q)| at the constraints' multipliers; infinity outside the domain.
  double residual_norm(const Eigen::VectorXd& q, Vec u);
  // Seconds spent in the elements and in the constraints' forces so far.
  double element_seconds() const { return element_s_; }
  double constraint_seconds() const { return constraint_s_; }

 private:
  // Adds the contact nodes' barrier forces and (K not null) Hessians at ua. False where a
  // node is on or inside an obstacle.
  bool add_contact(const PetscScalar* ua, Eigen::VectorXd& r, Eigen::MatrixXd* K);
  // Adds the sampled patches' weighted terms (a nodal-pressure body) to r and the tangent K
  // (may be null), at local displacements ua. False where a patch inverts.
  bool add_patches(const PetscScalar* ua, Eigen::VectorXd& r, Eigen::MatrixXd* K);
  // r(q) (false where an element inverts or a constraint leaves its domain); `tangent`: also
  // the elements' part of dr/dq; `forces`: also the constraints' projected forces.
  bool residual(const Eigen::VectorXd& q, Vec u, Eigen::VectorXd& r, Eigen::MatrixXd* tangent,
                Eigen::VectorXd* forces = nullptr);
  // Phi_S^T f_c(u): the constraints' forces projected, or false; their unit forces at u into
  // G. One pass over each constraint's walls or path: the forces are sum_c lambda_c G_c
  // plus the projected measure loads (ConstraintSet::measure).
  bool constraint_forces(Vec u, Eigen::VectorXd& p, Eigen::MatrixXd& G);
  // Phi_S^T v for a vector v whose support is sampled.
  Eigen::VectorXd project_sampled(Vec v) const;
  // Each constraint's unit forces Phi^T g_c at u (one column per constraint).
  Eigen::MatrixXd unit_forces(Vec u);
  Eigen::MatrixXd project_unit_forces(Vec u);  // the same, untimed
  // Each constraint's stiffness per unit multiplier, Phi^T (dg_c/du) Phi, by forward
  // differences of g_c along each mode (the walls' follower stiffness, a cable's turning), and
  // the unit forces G at q.
  void refresh_stiffness(const Eigen::VectorXd& q, Vec u, Eigen::MatrixXd& G);
  // The constraints' part of dr/dq (the caller subtracts it): sum_c lambda_c of the current
  // multipliers times its unit stiffness, and a liquid's weight following the volume.
  Eigen::MatrixXd constraint_tangent() const;
  std::vector<double> multipliers() const;
  void prescribe(const Eigen::VectorXd& lambda);  // the model's actuators' multipliers

  Problem& problem_;
  ConstraintSet& constraints_;
  Eigen::MatrixXd phi_;            // (3 N) x k, local dof order (one rank: all dofs)
  std::vector<PetscInt> sample_;   // the sampled dofs, ascending
  Eigen::MatrixXd phi_sample_;     // Phi's rows at the sampled dofs
  std::vector<int64_t> elements_;  // local tetrahedra of the hyper-reduction
  std::vector<double> weights_;
  std::vector<Eigen::MatrixXd> phi_element_;  // Phi's rows at each element's dofs
  struct SampledPatch {
    int32_t node;  // local
    double weight;
    std::vector<int64_t> elements;  // the patch's local tets
    std::vector<int> slots;         // per element's vertex, its node's place in the patch's
    Eigen::MatrixXd phi;            // Phi's rows at the patch's nodes' dofs
  };
  std::vector<SampledPatch> patches_;
  const NodalPressure* nodal_ = nullptr;
  // Contact with obstacles: every contact node's barrier, evaluated on the reconstructed
  // surface (no sampling: a node's term is cheap and only the nodes near an obstacle carry
  // one), with Phi's rows at each node.
  const ObstacleContact* contact_ = nullptr;
  std::vector<Eigen::Matrix<double, 3, Eigen::Dynamic>> phi_contact_;
  std::vector<NodeContact> contact_terms_;
  Eigen::VectorXd dead_;        // Phi^T f_dead
  Eigen::MatrixXd residual_G_;  // the unit forces at the last residual's u
  VecHandle work_;
  std::vector<int> actuators_;  // the model's actuators, indices into constraints_
  Eigen::MatrixXd training_actuations_, training_states_;
  Eigen::VectorXd training_range_;
  // Per constraint, the last unit stiffness; the unit forces of the last linearization.
  std::vector<Eigen::MatrixXd> unit_stiffness_;
  Eigen::MatrixXd unit_forces_;
  // Broyden's correction to constraint_tangent() and the last linearization's point: q, the
  // constraints' projected forces, their multipliers and unit forces.
  Eigen::MatrixXd secant_;
  struct {
    Eigen::VectorXd q, p;
    std::vector<double> lambda;
    Eigen::MatrixXd G;
  } last_;
  double element_s_ = 0, constraint_s_ = 0;
  double force_scale_ = 1;
};

}  // namespace hs
