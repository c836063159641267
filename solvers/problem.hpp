// The discrete problem one rank works on (equation 1 of the paper without actuators):
//   R(u; s) = f_int(u) - s f_body - f_pressure(u; s) [+ c M (u - u_pred)] = 0,
// s the load factor. Its PETSc objects: ghosted block vectors (3 dofs per node, the
// layout of hs::Distribution) and an AIJ matrix of block size 3 with the rigid-body
// near-null space attached, assembled by coordinates (see tangent_entries). Dirichlet dofs keep
// their rows: R_D = u_D - g_D(s) and identity rows/columns in the tangent, so the tangent stays
// symmetric when the physics is (the solution always satisfies the constraints before a Newton
// solve, hence the zeroed columns lose nothing).
#pragma once

#include <petscksp.h>
#include <petscmat.h>
#include <petscvec.h>

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "deck/config.hpp"
#include "fem/element.hpp"
#include "materials/material.hpp"
#include "materials/volumetric_term.hpp"
#include "mesh/distribution.hpp"
#include "mesh/mesh.hpp"
#include "solvers/dof_map.hpp"
#include "solvers/nodal_pressure.hpp"
#include "solvers/node_pair_blocks.hpp"
#include "solvers/obstacle_contact.hpp"
#include "solvers/petsc_check.hpp"
#include "solvers/petsc_handle.hpp"
#include "solvers/self_contact.hpp"

namespace hs {

// Inertia of an implicit time step: the term c M (u - u_pred) (Newmark or backward Euler).
struct InertiaTerm {
  MatHandle M;  // consistent mass matrix (unit diagonal on Dirichlet rows)
  VecHandle u_pred;
  double c = 0;
};

// contact_s: the contact's own work (obstacles' and self-contact's forces, tangents, pair
// searches and step limits), the most part inside residual_s and jacobian_s.
struct AssemblyTimers {
  double residual_s = 0, jacobian_s = 0, contact_s = 0;
  int residual_calls = 0, jacobian_calls = 0;
};

// Adds the seconds of its scope to `total`.
class AddSeconds {
 public:
  explicit AddSeconds(double& total) : total_(total), start_(MPI_Wtime()) {}
  ~AddSeconds() { total_ += MPI_Wtime() - start_; }
  AddSeconds(const AddSeconds&) = delete;
  AddSeconds& operator=(const AddSeconds&) = delete;

 private:
  double& total_;
  double start_;
};

// The checkpoint's field of the volume multipliers (Problem::volume_multiplier_field).
inline constexpr char kVolumeMultiplierField[] = "volume_multipliers";
// The checkpoint's element field of the F-bar elements' volume multipliers.
inline constexpr char kFbarMultiplierField[] = "fbar_volume_multipliers";

class Problem {
 public:
  // `exact` (may be empty) gives the values of Dirichlet conditions marked exact; `body_force`
  // (may be empty) a body force field added to gravity's (a manufactured solution's).
  Problem(const Config& config, const Distribution& dist, MPI_Comm comm, ExactDirichlet exact = {},
          const ForceDensity& body_force = {});
  ~Problem();
  Problem(const Problem&) = delete;
  Problem& operator=(const Problem&) = delete;

  MPI_Comm comm() const { return comm_; }
  const Distribution& distribution() const { return dist_; }
  PetscInt num_global_dofs() const { return 3 * static_cast<PetscInt>(dist_.num_global()); }

  Vec create_vector() const { return dofs_.create_vector(comm_); }  // ghosted, zeroed
  // The tangent's matrix: its pattern given once by coordinates (tangent_entries), the
  // near-null space attached. After the first one, no cavity surface or coupling may be added.
  // With `mixed` and a nodal-pressure body, the tangent's mixed system
  // (solvers/mixed_factor.hpp) is composed on it and filled with it.
  Mat create_matrix(bool mixed = false);
  Mat create_mass_matrix();
  bool has_nodal_pressure() const { return nodal_ != nullptr; }
  // Exactly incompressible bodies (nu = 0.5): the volume multipliers of the nodal-pressure
  // element's patches (solvers/nodal_pressure.hpp) and of the F-bar elements, raised by
  // solvers/incompressibility.hpp (solvers/problem_multipliers.cpp).
  bool has_volume_multipliers() const { return has_volume_multipliers_; }
  // The largest |ln J| of a patch or element that has a multiplier, on u, over all ranks.
  // Collective.
  double largest_volume_change(Vec u);
  // The multipliers' raise k ln J of each (after largest_volume_change(u)), in the order of
  // volume_multipliers(): the patches' (local nodes), then the F-bar elements' (local tets).
  std::vector<double> volume_multiplier_raise() const;
  std::vector<double> volume_multipliers() const;
  void set_volume_multipliers(const std::vector<double>& lambda);
  // The penalty of exactly incompressible F-bar elements: `scale` times their law's (1 until
  // set; the nodal-pressure element keeps its law's).
  void scale_fbar_penalty(double scale);
  // sum of a_i b_i over the multipliers this rank owns, over all ranks. Collective.
  double multiplier_dot(const std::vector<double>& a, const std::vector<double>& b) const;
  // The patches' multipliers as a nodal field for the checkpoint (first component; the others
  // 0), and back from one (collective: the ghosts are updated from their owners); the F-bar
  // elements', a value per local tet (empty without them), and back.
  bool has_nodal_volume_multipliers() const { return nodal_ && nodal_->has_multipliers(); }
  void volume_multiplier_field(Vec field) const;
  void set_volume_multipliers(Vec field);
  bool has_fbar_volume_multipliers() const { return has_fbar_multipliers_; }  // on every rank
  const std::vector<double>& fbar_volume_multipliers() const { return fbar_lambda_; }
  void set_fbar_volume_multipliers(const std::vector<double>& lambda) { fbar_lambda_ = lambda; }
  // What keeping the volumes took, over the run's converged solves (summary.json's
  // `incompressibility`).
  struct VolumeKeeping {
    int solves = 0, raises = 0, most_raises = 0;
    double last_change = 0;  // the largest |ln J_a| the last solve left
  };
  const VolumeKeeping& volume_keeping() const { return volume_keeping_; }
  void record_volumes_kept(double change, int raises) {
    ++volume_keeping_.solves;
    volume_keeping_.raises += raises;
    volume_keeping_.most_raises = std::max(volume_keeping_.most_raises, raises);
    volume_keeping_.last_change = change;
  }

  // Sets the Dirichlet dofs of u to their prescribed values at load factor s.
  void apply_dirichlet(Vec u, double s) const { dofs_.apply(u, s); }
  // A translation added to a boundary group's prescribed values (a state's `move`), and the
  // present one.
  void move_boundary(const std::string& group, const std::array<double, 3>& by) {
    dofs_.set_move(group, by);
  }
  std::array<double, 3> boundary_moved(const std::string& group) const {
    return dofs_.moved(group);
  }
  // Every group's translation, and the same set back (DofMap::moves).
  const DofMap::Moves& boundary_moves() const { return dofs_.moves(); }
  void set_boundary_moves(const DofMap::Moves& moves) { dofs_.set_moves(moves); }

  // Residual and tangent. Return false if an element is inverted (det F <= 0) or a
  // value is not finite; inverted_element() then names one such element on every rank (its
  // mesh index, the highest of them), and is -1 after an evaluation that found none.
  bool residual(Vec u, double s, Vec R);
  // Newton's tangent: the volumetric pressure of nodal-pressure and F-bar bodies is linearised
  // from the previous tangent's point (docs/formulation.md), so that it is J itself at that
  // point and within O(|u - u0|^2) of it elsewhere.
  bool jacobian(Vec u, double s, Mat J);
  // The next jacobian() is J itself at its point, whatever the previous one's: for uses of
  // the tangent other than Newton's step (the reduced model's error indicator).
  void exact_next_tangent();
  // The tangent's memory of the previous tangent's point (jacobian(), above), copied out and
  // put back around a solve that is not the caller's next step (the controller's equilibrium
  // check): its Newton iterates would otherwise be the point the caller's next tangent is
  // linearised from. Local to each rank. Per local tet of an F-bar material: ln Jbar(u0) -
  // g . u0 and g = b(u0) / Jbar(u0); the nodal pressures' is NodalPressure::Linearization.
  struct FbarLinearization {
    bool valid = false;
    double c0 = 0;
    std::array<double, 30> g{};
  };
  struct TangentMemory {
    NodalPressure::Linearization nodal;
    std::vector<FbarLinearization> fbar;
  };
  TangentMemory tangent_memory() const;
  void restore_tangent_memory(TangentMemory memory);
  int64_t inverted_element() const { return inverted_element_; }
  // The obstacle a node of the body was found on or inside by the last residual (its index in
  // the deck's list, over all ranks), or -1: the barrier refuses such a configuration as an
  // inverted element is refused.
  int obstacle_reached() const { return obstacle_reached_; }
  // Whether the last residual was refused for contact: an obstacle reached, or a node of the
  // contact surfaces on one of their triangles.
  bool contact_refused() const { return obstacle_reached_ >= 0 || self_touch_; }
  // Why the last residual was refused, in words: "inverted element" or "a node reached
  // obstacle 'NAME'".
  std::string refusal() const;
  // A converged state u at load factor s, from which the next step starts: contact friction
  // lags its normal forces and anchors from there (docs/contact.md) from the next
  // begin_solve() on. The Newton solvers call accept_state on convergence and begin_solve
  // before each solve. Collective.
  void accept_state(Vec u, double s);
  void begin_solve() {
    if (contact_) contact_->begin_step();
    if (self_contact_) self_contact_->begin_step();
  }
  // While held, accept_state does nothing: the control loop holds friction's lag over its
  // solves (trial and check solves included) and accepts each answered state with
  // take_friction_lag (collective), which the next begin_solve() makes the lag.
  void hold_friction_lag(bool held) { friction_lag_held_ = held; }
  void take_friction_lag(Vec u, double s);
  // Contact with the deck's obstacles (null without them).
  const ObstacleContact* contact() const { return contact_.get(); }
  ObstacleContact* contact() { return contact_.get(); }
  // Contact of the contact surfaces with each other (null without contact.self).
  const SelfContact* self_contact() const { return self_contact_.get(); }
  bool has_contact() const { return contact_ || self_contact_; }
  // Counts the times self-contact's tangent pattern grew: a solver whose factorization was
  // analysed for an earlier pattern resets its preconditioner (PCReset).
  int pattern_version() const { return pattern_version_; }
  // Drops the factorization of ksp's preconditioner when the pattern grew since `seen` (the
  // version it was set up for, updated here): it does not notice the new pattern and would
  // refactor on the old analysis (MUMPS failed so on 2 ranks).
  void reset_if_pattern_grew(KSP ksp, int& seen) const;
  // Its totals on u (SelfContact::totals). Collective; without contact.self zeros.
  SelfContact::Totals self_contact_totals(Vec u) const;
  // Its gap and pressure per owned node (SelfContact::node_values). Collective; without
  // contact.self empty.
  SelfContact::NodeValues self_contact_node_values(Vec u) const;
  // Per obstacle, the force the body exerts on it and its touching area, on u at load
  // factor s. Collective; empty without obstacles.
  ObstacleContact::Totals contact_totals(Vec u, double s) const;
  // The force on obstacle o of the contact nodes where only[n] is set (per local node; all
  // without `only`), over all ranks, and its derivative with respect to u as three
  // distributed rows, zero on Dirichlet dofs (ObstacleContact::force_on, force_rows).
  // Collective; without obstacles zero.
  std::array<double, 3> contact_force(Vec u, double s, int o,
                                      const std::vector<char>* only = nullptr) const;
  // Where none of those nodes is within the barrier's reach (the force and its rows are
  // zero), the rows are n n^T at the nearest of them instead (n the obstacle's normal there:
  // a unit spring across its gap, for a force target to close the gap; docs/control.md), and
  // the return value is that gap; else 0.
  double contact_force_rows(Vec u, double s, int o, const std::vector<char>* only,
                            Vec rows[3]) const;
  // The force contact surface a exerts on b (indices in contact.surfaces) and its rows, as
  // contact_force and contact_force_rows (SelfContact::force_between, force_rows_between).
  // Collective; without contact.self zero.
  std::array<double, 3> self_contact_force(Vec u, int a, int b) const;
  double self_contact_force_rows(Vec u, int a, int b, Vec rows[3]) const;
  // The largest fraction <= 1 of the step du from u (at load factor s) that keeps every
  // contact node outside the obstacles (ObstacleContact::step_limit) and every node a tenth
  // of its distance off the triangles of the surfaces (SelfContact::step_limit), over all
  // ranks; 1 without contact. Collective.
  double contact_step_limit(Vec u, Vec du, double s) const;
  // Its self-contact part alone (1 without contact.self). Collective.
  double self_contact_step_limit(Vec u, Vec du) const;
  // A step's predicted start u (extrapolated, its Dirichlet values at s set) that would bring
  // a node of the contact surfaces through or near a triangle on the way from the converged
  // `from` is taken back to `from` with the Dirichlet values at s: self-contact's distances
  // are unsigned, so no residual would refuse it, and Newton walks there instead with its
  // steps limited. One that comes nearer an obstacle than a tenth of a node's gap (on or
  // inside it the residual would be refused, the step cut back; just outside the barrier's
  // force would be huge) is shortened to keep that tenth, as Newton's steps are.
  // Collective.
  void keep_outside_contact(Vec from, Vec u, double s) const;
  // Per owned node, the contact's fields (ObstacleContact::node_values); empty without
  // obstacles. Collective. On P2 meshes both contacts' pressure and friction are their
  // faces' means (face_means).
  ObstacleContact::NodeValues contact_node_values(Vec u, double s) const;

  void set_inertia(const InertiaTerm* inertia) { inertia_ = inertia; }
  bool has_inertia() const { return inertia_ != nullptr; }  // during a time step's solve

  // The applied external load at load factor s on configuration u (gravity + pressure).
  void external_load(Vec u, double s, Vec f);

  // Sum over the owned nodes of `group` of f(X, value of v at the node), over all ranks.
  // Used for reactions and averages over node groups.
  template <class F>
  double sum_over_group(const std::string& group, Vec v, F f) const;

  // Internal forces f_int(u) alone (no loads, no Dirichlet rows): at constrained nodes these
  // are the reactions.
  // Optionally also the stored energy int psi dV (summed over ranks) in *energy.
  void internal_force(Vec u, Vec f, double* energy = nullptr);

  // Whether the residual is the gradient of a potential energy: no follower pressure and no
  // extra load (gravity, Dirichlet data and inertia are conservative).
  bool has_potential() const { return pressure_faces_.empty() && !extra_load_; }
  // As has_potential, the cavities' closed walls allowed: at pressures held fixed, each adds
  // -p V to the potential (the bordered Newton's merit with self-contact).
  bool has_potential_at_held_pressures() const {
    return !has_open_surface_pressure() && !extra_load_;
  }
  // That energy, Pi(u; s) = int psi dV - s f_body . u - sum_cavities p V(u)
  // [+ c/2 (u - u_pred)^T M (u - u_pred)], in *energy; false (and *energy untouched) on an
  // inverted element. Requires has_potential_at_held_pressures().
  bool potential_energy(Vec u, double s, double* energy);
  // The round-off of the residual's evaluation at u: eps || sum_e |K_e| (|u_e| + |X_e - c_e|) ||
  // (c_e the element's centroid), over the free dofs. Forming F = I + grad u from
  // displacements of size |u| and element size h loses eps |u| / h and eps in F; the tangent
  // carries that to the nodal forces. On fine meshes under body loads this floor exceeds
  // 1e-8 of the load (the 10M-dof cantilever: 3e-8), which a relative test alone never meets.
  double residual_roundoff(Vec u);
  double reference_coordinate(int64_t local_node, int d) const { return X_[3 * local_node + d]; }

  // Whether every tetrahedron keeps its orientation on configuration u (J > 0 at its
  // centroid, so a finite stress; over all ranks): the cheap check of a configuration no
  // residual has seen, from positions alone. Records an inverted one as inverted_element().
  bool orientation_preserved(Vec u);

  // Per local tetrahedron, at the centroid (fem/element.hpp's tet_fields): von Mises stress,
  // J, the Cauchy stress and the Green-Lagrange strain (9 values each, row-major) and their
  // principal values (3 each, largest first; left empty without `principal`: finite
  // tensors have finite ones, and they cost most of the pass).
  struct ElementFieldValues {
    std::vector<double> von_mises, J, stress, strain, principal_stress, principal_strain;
  };
  void element_fields(Vec u, ElementFieldValues& values, bool principal = true) const;
  // The nodal-pressure element's pressure per owned node on configuration u (positive in
  // compression, NodalPressure::owned_compression); empty without that element. Collective.
  std::vector<double> nodal_pressure(Vec u) const;

  // Reactions: per group of the deck's `boundary` list (reaction_groups(), in the deck's
  // order, each group once), the force the constraint exerts on the body, summed over its
  // constrained dofs: f_int(u) - f_ext(u; s) there, the residual's Dirichlet rows before they
  // are replaced (inertia left out). A dof that several groups constrain counts in the first
  // of them only, so that the groups sum to the total reaction. Each owned dof is counted by
  // its rank alone. Collective.
  const std::vector<std::string>& reaction_groups() const { return dofs_.groups(); }
  std::vector<std::array<double, 3>> reactions(Vec u, double s);
  // The mean displacement of a surface group, int u dA / int dA over its reference faces (its
  // centroid's displacement). Collective.
  std::array<double, 3> mean_displacement(const std::string& group, Vec u);

  // The ghost-updated local form (owned then ghost nodes) of a vector, readable while alive.
  class LocalView;

  const AssemblyTimers& timers() const { return timers_; }
  // Internal force (and tangent, K not null) of local tet e at local displacements ua (owned
  // then ghost nodes, 3 each): one element's part of f_int. In a nodal-pressure body that
  // part includes, with `patch_share`, the element's share of its nodes' patch terms at the
  // last assembly's pressures; a reduced model samples elements without it and the patch
  // terms apart (nodal_pressure()->patch_term).
  ElementOutput element_force(int64_t e, const PetscScalar* ua, double* r, double* K,
                              bool patch_share = true) const;
  // The nodal-pressure element's patch terms (null without a nodal-pressure body).
  const NodalPressure* nodal_pressure() const { return nodal_.get(); }
  bool has_follower_loads() const { return !pressure_faces_.empty(); }
  // Pressure loads of the deck (open surfaces: not conservative, so their load stiffness is
  // not symmetric). A cavity's pressure on its closed walls is conservative (the potential
  // -p V): its load stiffness p d2V/du2 is symmetric.
  bool has_open_surface_pressure() const {
    for (const auto& s : pressure_faces_)
      if (s.scaled) return true;
    return false;
  }

  // Cavity walls (solvers/constraints/cavity.hpp; problem_surfaces.cpp). A cavity surface is a
  // follower pressure surface whose pressure is set directly (not scaled by the load factor);
  // returns its index.
  int add_cavity_surface(const std::string& group);
  bool has_cavity_surfaces() const {
    for (const auto& s : pressure_faces_)
      if (!s.scaled) return true;
    return false;
  }
  void set_surface_pressure(int surface, double p) { pressure_faces_[surface].value = p; }
  // Volume enclosed by the surface on configuration u (summed over ranks; faces point out of
  // the body, so a cavity's volume is positive).
  double enclosed_volume(int surface, Vec u);
  // g = dV/du of that volume: the nodal forces of a unit pressure (the paper's J_p^T), zero on
  // Dirichlet dofs.
  void volume_gradient(int surface, Vec u, Vec g);
  // The pressure of the cavity surfaces alone (the part of external_load they are) on
  // configuration u, into f.
  void cavity_pressure_load(Vec u, Vec f);
  // A further load vector f (not owned; nullptr for none): R -= f, external_load += f.
  void set_extra_load(Vec f) { extra_load_ = f; }
  // int n da over the deformed faces of a surface group (summed over ranks): its area times
  // its mean outward normal.
  std::array<double, 3> area_vector(const std::string& group, Vec u);
  // Registers a block of the tangent that another term provides (a cable's turning
  // stiffness): all pairs of `dofs` (global, -1 skipped), on the rank that will set it.
  // Returns its index. set_coupling gives its values (row-major, |dofs|^2) for the next
  // tangents; zero until set.
  int add_coupling(std::vector<PetscInt> dofs);
  void set_coupling(int k, const std::vector<PetscScalar>& values);
  // Zeroes the Dirichlet dofs of a vector (owned entries).
  void zero_constrained(Vec v) const { dofs_.zero(v); }
  // Whether a local dof (3 per local node) is held by a Dirichlet condition.
  bool constrained(int64_t local_dof) const { return dofs_.constrained(local_dof); }

 private:
  // contact_step_limit's obstacle part (1 without obstacles). Collective.
  double obstacle_step_limit(Vec u, Vec du, double s) const;
  struct PressureSurface {
    std::vector<int32_t> faces;  // local node indices, nodes_per_face each
    double value;
    bool scaled = true;  // the pressure is value * load factor (cavities: value as is)
  };
  double pressure_at(const PressureSurface& surface, double s) const {
    return surface.scaled ? s * surface.value : surface.value;
  }
  // Adds per-local-node contributions computed by `add(u_local, r_local)` into `out`
  // (through the ghosted local form and a reverse ghost update).
  template <class F>
  void assemble_local(Vec u, Vec out, F add);
  Mat create_pattern_matrix();  // the tangent's pattern, no mixed system
  // The tangent's entries (tangent_entries, then the patch coupling's), and its values
  // sized to them.
  void pattern_entries(std::vector<PetscInt>& rows, std::vector<PetscInt>& cols);
  // J (and its mixed system) preallocated again where self-contact's pattern grew since.
  void update_pattern(Mat J);
  // The mixed system of a nodal-pressure body's tangent, its pattern by coordinates.
  Mat create_mixed_matrix();
  void preallocate_mixed(Mat mixed);
  // Its values for the tangent whose values tangent_values_ holds.
  void fill_mixed_matrix(Mat mixed);
  void element_coordinates(int64_t local_tet, double* X) const;
  void element_displacement(const PetscScalar* u_local, int64_t local_tet, double* u) const;
  bool assemble_forces(Vec u, double s, double a, double b, Vec out, double* energy);
  // Collective: agrees on this rank's inverted element (-1: none) with the others, records
  // it and returns whether there is none.
  bool record_inverted(int64_t local_bad);
  // Newton's tangent of local tet e: element_force's, but for an F-bar element of a law with
  // the volumetric term, whose pressure is Newton's own, linearised from the previous
  // tangent's point (docs/formulation.md); the point is kept for the next one.
  ElementOutput element_tangent(int64_t e, const PetscScalar* ua, double* r, double* K);
  // The tangent's entries by coordinates, in the order jacobian() fills their values: the
  // node-pair blocks (elements and faces summed into them), Dirichlet diagonals, registered
  // couplings.
  void tangent_entries(std::vector<PetscInt>& rows, std::vector<PetscInt>& cols) const;
  // Writes the values of the entries after the node-pair blocks (Dirichlet diagonals,
  // couplings) from `value` on.
  void fill_constraint_entries(PetscScalar* value) const;

  MPI_Comm comm_;
  const Distribution& dist_;
  int npe_;
  std::vector<MaterialConfig> materials_;  // per mesh volume group: its law and density
  // Per mesh volume group: the law its elements integrate (a nodal-pressure material's less
  // its volumetric term, which nodal_ integrates per node).
  std::vector<std::shared_ptr<const MaterialLaw>> element_laws_;
  std::unique_ptr<NodalPressure> nodal_;  // when a material runs the nodal-pressure element
  VolumeKeeping volume_keeping_;
  // Per mesh volume group: an F-bar material's law less its volumetric term (null for others
  // and for small-strain laws); per local tet, where any is, the previous tangent's point of
  // the term (FbarLinearization).
  std::vector<std::shared_ptr<const WithoutVolumetricTerm>> fbar_rest_laws_;
  // Per mesh volume group: the modulus k of the split term k/2 (ln Jbar)^2, the law's own but
  // for exactly incompressible materials, whose penalty F-bar takes lower
  // (kFbarIncompressiblePenalty, docs/formulation.md).
  std::vector<double> fbar_modulus_;
  std::vector<FbarLinearization> fbar_linearization_;
  // Exactly incompressible F-bar elements: per local tet, whether, the multiplier, and ln Jbar
  // at the last largest_volume_change (empty without such a material).
  std::vector<char> fbar_incompressible_;
  std::vector<double> fbar_lambda_, fbar_ln_Jbar_;
  bool fbar_incompressible(int64_t e) const {
    return !fbar_incompressible_.empty() && fbar_incompressible_[e];
  }
  // The split term of F-bar element e (a split material's): its rest law, modulus and
  // multiplier.
  FbarNewtonPressure fbar_pressure(int64_t e) const;
  // A P2 body balances a contact pressure with consistent nodal forces, which leave a face's
  // corners almost nothing, so a node's force over its share of the area alternates between
  // about 0 and 2 p across a face pressed by p. Each face's mean of those values, taken back
  // to its nodes as their faces' mean, is p again: `values` (width per owned node) so
  // averaged over the contact surfaces' faces on P2 meshes, unchanged on P1. Collective.
  void face_means(std::vector<double>& values, int width) const;
  std::vector<std::string> contact_surfaces_;  // the deck's contact.surfaces
  bool has_volume_multipliers_ = false;
  bool has_fbar_multipliers_ = false;          // the deck's materials: the same on every rank
  std::unique_ptr<ObstacleContact> contact_;   // with obstacles
  std::unique_ptr<SelfContact> self_contact_;  // with contact.self
  bool self_touch_ = false;                    // the last residual's: a node on a triangle
  // Self-contact's pattern grows (SelfContact::extend_pattern): each matrix made here with
  // the version of the pattern it was preallocated for.
  int pattern_version_ = 0;
  std::map<Mat, int> matrix_pattern_;
  bool friction_lag_held_ = false;
  DofMap dofs_;
  const std::vector<double>& X_;         // reference coordinates of local nodes
  std::vector<double> body_force_;       // per local tet: npe*3, at full load
  std::vector<P1Geometry> p1_geometry_;  // per local tet of a P1 mesh (empty for P2)
  std::vector<PressureSurface> pressure_faces_;
  // Dead tractions: the faces of their groups (nodes_per_face local nodes each) and each
  // face's nodal forces at full load (3 nodes_per_face each), computed once.
  std::vector<int32_t> traction_faces_;
  std::vector<double> traction_forces_;
  const InertiaTerm* inertia_ = nullptr;
  Vec extra_load_ = nullptr;
  std::vector<std::vector<PetscInt>> couplings_;
  std::vector<std::vector<PetscScalar>> coupling_values_;
  std::unique_ptr<NodePairBlocks> pairs_;    // made with the first matrix
  std::vector<PetscScalar> tangent_values_;  // one per entry of tangent_entries
  std::vector<PetscScalar> mass_values_;     // the mass matrix's, in the same order
  // The mixed system's entries: the tangent's without the patch coupling, then G, G^T and the
  // pressure block (NodalPressure::mixed_entries); their values.
  std::vector<PetscInt> mixed_rows_, mixed_cols_;
  std::vector<PetscScalar> mixed_values_;
  bool pattern_fixed_ = false;  // a matrix exists: no new surfaces or couplings
  VecHandle u_work_, r_work_;
  int64_t inverted_element_ = -1;  // of the last residual or tangent, over all ranks
  int obstacle_reached_ = -1;      // of the last residual, over all ranks
  mutable AssemblyTimers timers_;  // mutable: the step limits are const and timed
};

class Problem::LocalView {
 public:
  LocalView(Vec u, Vec work) : work_(work) {
    HS_PETSC(VecCopy(u, work_));
    HS_PETSC(VecGhostUpdateBegin(work_, INSERT_VALUES, SCATTER_FORWARD));
    HS_PETSC(VecGhostUpdateEnd(work_, INSERT_VALUES, SCATTER_FORWARD));
    HS_PETSC(VecGhostGetLocalForm(work_, &local_));
    HS_PETSC(VecGetArrayRead(local_, &values_));
  }
  ~LocalView() {
    VecRestoreArrayRead(local_, &values_);
    VecGhostRestoreLocalForm(work_, &local_);
  }
  const PetscScalar* values() const { return values_; }

 private:
  Vec work_, local_ = nullptr;
  const PetscScalar* values_ = nullptr;
};

template <class F>
void Problem::assemble_local(Vec u, Vec out, F add) {
  LocalView view(u, u_work_);
  Vec rl;
  HS_PETSC(VecGhostGetLocalForm(r_work_, &rl));
  HS_PETSC(VecSet(rl, 0.0));
  PetscScalar* ra;
  HS_PETSC(VecGetArray(rl, &ra));
  add(view.values(), ra);
  HS_PETSC(VecRestoreArray(rl, &ra));
  HS_PETSC(VecGhostRestoreLocalForm(r_work_, &rl));
  HS_PETSC(VecGhostUpdateBegin(r_work_, ADD_VALUES, SCATTER_REVERSE));
  HS_PETSC(VecGhostUpdateEnd(r_work_, ADD_VALUES, SCATTER_REVERSE));
  HS_PETSC(VecCopy(r_work_, out));
}

template <class F>
double Problem::sum_over_group(const std::string& group, Vec v, F f) const {
  double local = 0;
  auto it = dist_.node_groups.find(group);
  if (it != dist_.node_groups.end()) {
    const PetscScalar* a;
    HS_PETSC(VecGetArrayRead(v, &a));
    for (int32_t n : it->second) {
      if (n >= dist_.num_owned()) continue;  // ghosts are counted by their owner
      const std::array<double, 3> X = {X_[3 * n], X_[3 * n + 1], X_[3 * n + 2]};
      const std::array<double, 3> value = {a[3 * n], a[3 * n + 1], a[3 * n + 2]};
      local += f(X, value);
    }
    HS_PETSC(VecRestoreArrayRead(v, &a));
  }
  double total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return total;
}

}  // namespace hs
