// control.contact_forces: qp (docs/control.md, "Contact forces in the QP"): the obstacles'
// normal forces on the contact nodes are unknowns of the controller's QP beside the
// actuation, as SOFA's inverse solver takes them, in place of the barrier inside the free
// configuration. This is the FEM side of control/contact_actuation_qp.hpp: the free
// configuration holds each node's force as a constant load (ObstacleContact's held forces);
// at x_free the candidates (contact nodes within reach of an obstacle, or holding a force)
// each get the whole system's response to a unit normal force, from the step's factorization
// and bordered elimination with the actuators held; from those, the gaps' and the effectors'
// dependence on the forces; after the QP, the correction adds the forces' responses and
// holds the new forces. Every call is collective.
#pragma once

#include <petscksp.h>

#include <Eigen/Dense>
#include <vector>

#include "control/contact_actuation_qp.hpp"
#include "solvers/bordered_system.hpp"
#include "solvers/effectors.hpp"
#include "solvers/petsc_handle.hpp"
#include "solvers/problem.hpp"

namespace hs {

class ContactQp {
 public:
  ContactQp(Problem& problem, Effectors& effectors);

  // A step's start: the first time, the barrier gives way to held forces (the barrier's
  // normal forces at u).
  void begin_step(Vec u);
  // At x_free, after the bordered elimination with the actuators held (`held`) and their
  // responses: the candidates and their responses, and the blocks of the QP. W_a and delta
  // are the effectors' rows as the controller forms them (a force effector's row over dl
  // zero), in the targets' order, one per controlled direction.
  ContactBlocks linearize(Vec u, KSP ksp, BorderedSystem& system,
                          const ConstraintLinearization& lin, const std::vector<bool>& held,
                          const std::vector<Vec>& actuator_responses,
                          const std::vector<int>& actuator_constraints,
                          const std::vector<ControlTarget>& targets, const Eigen::MatrixXd& W_a,
                          const Eigen::VectorXd& delta);
  // u += sum_j du_j dforce_j and the candidates hold their new forces, along the obstacles'
  // normals where the nodes now are; the change of every constraint's multiplier that those
  // forces bring.
  Eigen::VectorXd apply(Vec u, const Eigen::VectorXd& dforce);
  int num_candidates() const { return static_cast<int>(normal_.size()); }

 private:
  Problem& problem_;
  Effectors& effectors_;
  ObstacleContact& contact_;
  double reach_, gap_tolerance_;
  VecHandle work_;
  // This step's candidates over all ranks, in rank order: their obstacle and normal, and
  // this rank's own ones (their index in the contact's nodes, from offset_ on).
  std::vector<int> obstacle_;
  std::vector<Eigen::Vector3d> normal_;
  std::vector<ObstacleContact::Candidate> own_;
  int offset_ = 0;
  VecArray load_, response_;  // per candidate: its unit normal force, the response to it
  Eigen::MatrixXd zeta_;      // per candidate: the elimination's multipliers (columns)
};

}  // namespace hs
