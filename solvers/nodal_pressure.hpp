// The volumetric energy of a P1 body integrated per node (docs/formulation.md, "Nearly
// incompressible bodies on P1 meshes"): the averaged-nodal-pressure tetrahedron. Each element
// of a nodal-pressure material integrates its law less the stiff term k/2 (ln J)^2
// (materials/volumetric_term.hpp); that term is integrated over the patch of elements around
// each node a, on the patch's volume ratio:
//   Pi_vol = sum_a kV_a U1(J_a),   U1(J) = (ln J)^2 / 2,   J_a = v_a / V_a,
//   v_a = sum_(e at a) v_e / 4,   V_a = sum V_e / 4,   kV_a = sum k_e V_e / 4.
// Its force is element-local once the nodal pressures p_a = kV_a U1'(J_a) / V_a are known:
//   r = sum_e pbar_e dv_e/du,   pbar_e = the mean of p_a over e's four nodes;
// its tangent adds pbar_e d2v_e/du2 per element and the patch coupling
//   sum_a c_a g_a g_a^T,   c_a = kV_a U1''(J_a) / V_a^2,   g_a = dv_a/du = sum_(e at a) dv_e/du /
//   4,
// which joins every two nodes of a's patch: the tangent's stencil reaches the neighbours'
// neighbours. The coupling is G^T D G (G the matrix of the g_a, D = diag(c_a)), formed by PETSc
// (MatPtAP) over all ranks, so that a patch cut by a rank boundary is summed exactly.
// One nodal volume ratio per node, not per element: a body of n nodes carries n volumetric
// constraints against 3 n displacements, where the displacement element carries one per
// element (about 5.5 n), and so does not lock.
// Newton's tangent takes the patch pressure as an unknown of its own, condensed per node (the
// mixed form sum_a V_a [q_a ln J_a - q_a^2 / (2 kbar_a)], kbar_a = kV_a / V_a, has the same
// solutions): its step is the displacement step with the tangent's pressure linearised from
// the previous tangent's point, q_a = kbar_a (ln J_a + d(ln J_a) . du), instead of kbar_a ln J_a
// at u. The residual is the same; the tangents differ away from equilibrium only. A full step
// that overshoots the nearly rigid volume makes kbar ln J(u) huge and q not: Newton's
// iterations stop growing with k (docs/formulation.md).
// Exactly incompressible materials (nu = 0.5) add a multiplier lambda_a per node whose patch is
// all theirs (an augmented Lagrangian, Simo and Taylor 1991): the patch energy becomes
//   V_a [lambda_a M(J_a) + kbar_a M(J_a)^2 / 2],   M = ln J (J - 1 for small strains),
// kbar_a the penalty (materials/elastic_constants.hpp); each solve is repeated with
// lambda_a += kbar_a M(J_a) until every such patch keeps its volume
// (solvers/incompressibility.hpp).
#pragma once

#include <petscmat.h>
#include <petscvec.h>

#include <vector>

#include "fem/element.hpp"
#include "mesh/distribution.hpp"
#include "solvers/dof_map.hpp"
#include "solvers/petsc_handle.hpp"

namespace hs {

class NodalPressure {
 public:
  // modulus[e]: k_e of local tet e (< 0: the element is not a nodal-pressure one);
  // incompressible[e]: its material has nu = 0.5 (k_e is then the penalty); small_strain:
  // the laws are of small strains (U1 = (J - 1)^2 / 2 on the linearised volume change, the
  // linear elastic body's averaged nodal dilatation). Collective.
  NodalPressure(const Distribution& dist, const std::vector<P1Geometry>& geometry,
                std::vector<double> modulus, const std::vector<char>& incompressible,
                bool small_strain, const DofMap& dofs, MPI_Comm comm);

  // The volume multipliers (nodes whose patch is all of incompressible elements).
  bool has_multipliers() const { return has_multipliers_; }
  // Over all ranks, the largest |M(J_a)| of those nodes at the last update. Collective.
  double largest_volume_change() const;
  // Per local node, kbar_a M(J_a) at the last update where a has a multiplier, else 0: the
  // multipliers' raise (an augmented Lagrangian's update lambda += kbar M).
  std::vector<double> multiplier_raise() const;
  // Per local node, to put back after a failed solve.
  const std::vector<double>& multipliers() const { return lambda_; }
  void set_multipliers(const std::vector<double>& lambda) { lambda_ = lambda; }

  // From the local displacements (3 per local node, owned then ghosts): the volume ratios
  // and pressures of all local nodes. Collective. False if a patch's volume is not positive
  // (then `bad_tet` is a local tet at such a node).
  bool update(const PetscScalar* u_local, int64_t* bad_tet);
  bool takes_part(int64_t e) const { return modulus_[e] >= 0; }
  // pbar_e, the element's mean nodal pressure (tension positive): its Cauchy stress's
  // volumetric part.
  double element_pressure(int64_t e) const;
  // Newton's tangent at u (after update(u)): the pressures linearised from the previous call's
  // point (the first call, and small-strain bodies, take those of u), and this point kept for
  // the next call. Collective.
  void linearize(const PetscScalar* u_local);
  // The next linearize() takes the pressures of its own point: the exact tangent.
  void forget_linearization() { lin_.valid = false; }
  // The previous tangent's point: local displacements, per node ln J_a and v_a, per local tet
  // dv_e/du (12 each). Copied out and put back around a solve that is not the caller's next
  // Newton step (the controller's equilibrium check).
  struct Linearization {
    bool valid = false;
    std::vector<double> u, lnJ, v, grad;
  };
  const Linearization& linearization() const { return lin_; }
  void set_linearization(Linearization lin) { lin_ = std::move(lin); }
  // Adds pbar_e dv_e/du to r and, with the tangent's pressures (those of update() until
  // linearize()), pbar_e d2v_e/du2 to K (K may be nullptr) of local tet e.
  void add_element(int64_t e, const double* ue, double* r, double* K) const;
  // -p_a of the owned nodes (positive in compression; 0 at nodes of no nodal-pressure body).
  std::vector<double> owned_compression() const {
    std::vector<double> c(p_.begin(), p_.begin() + dist_.num_owned());
    for (double& x : c) x = -x;
    return c;
  }
  // sum of kV_a U1(J_a) over the owned nodes (this rank's share).
  double owned_energy() const;
  // Adds the element's own volumetric stiffness (k_e / V_e) dv_e/du (dv_e/du)^T to K: the
  // scale of the round-off of its nodal forces (Problem::residual_roundoff).
  void add_element_scale(int64_t e, const double* ue, double* K) const;

  // One node's patch term alone, for a reduced model that samples patches rather than
  // assembling them (one rank; solvers/reduced/reduced_system.hpp). `elements`: the patch's
  // tets (patch_elements()[n]); at local displacements ua its energy kV_a U1(J_a), pressure
  // p_a = kV_a U1'(J_a) / V_a and stiffness c_a = kV_a U1''(J_a) / V_a^2, and per element
  // dv_e/du (12 values in `grad`) and, with `hess`, d2v_e/du2 (144): the term's force is
  // p_a sum_e dv_e/du / 4, its tangent c_a g_a g_a^T + p_a sum_e d2v_e/du2 / 4. False where
  // the patch inverts. Not for a patch with a volume multiplier (nu = 0.5).
  struct PatchTerm {
    double energy = 0, p = 0, c = 0;
  };
  bool patch_term(int32_t n, const std::vector<int64_t>& elements, const PetscScalar* ua,
                  PatchTerm& term, double* grad, double* hess) const;
  // Per local node, the nodal-pressure tets around it (empty at a node of no such body).
  std::vector<std::vector<int64_t>> patch_elements() const;

  // The patch coupling's entries (owned rows, global dof indices), appended to rows/cols in
  // the order fill_coupling writes their values. Collective.
  void coupling_entries(std::vector<PetscInt>& rows, std::vector<PetscInt>& cols);
  size_t num_coupling_entries() const { return coupling_rows_.size(); }
  // The values of those entries at the displacements of the last update.
  void fill_coupling(const PetscScalar* u_local, PetscScalar* values);

  // The mixed system [K G^T; G -D^-1] (solvers/mixed_factor.hpp): its rows on each rank are the
  // rank's 3 no displacement rows, then its no pressure rows.
  PetscInt mixed_local_size() const { return 4 * static_cast<PetscInt>(dist_.num_owned()); }
  PetscInt mixed_dof(PetscInt dof) const;    // a global dof's row (negative stays negative)
  PetscInt mixed_node(PetscInt node) const;  // a global node's pressure row
  // Appends the entries of G, G^T and the pressure block, in the order fill_mixed writes them.
  // Collective (the first time).
  void mixed_entries(std::vector<PetscInt>& rows, std::vector<PetscInt>& cols);
  // Their values for the last fill_coupling: g_a, g_a again, -1 / c_a (-1 at a node of no
  // nodal-pressure body, whose G row is empty).
  void fill_mixed(PetscScalar* values) const;

 private:
  // The sums over patches of per-local-node values (each rank's elements' shares), complete
  // at every local node afterwards. Collective.
  void sum_over_patches(std::vector<double>& local_values);
  // G, D and the pattern of G^T D G (MatPtAP's symbolic product), once.
  void make_coupling();
  // M(J_a) of local node n at the last update: ln J_a (J_a - 1 for small strains).
  double volume_measure(size_t n) const;

  const Distribution& dist_;
  const std::vector<P1Geometry>& geometry_;
  std::vector<double> modulus_;  // per local tet
  bool small_strain_;
  std::vector<double> V_, kV_;    // per local node
  std::vector<double> lambda_;    // per local node: the volume multiplier (0 where none)
  std::vector<char> multiplied_;  // per local node: its patch is all incompressible
  bool has_multipliers_ = false;
  std::vector<double> dv_, p_, c_;  // per local node, at the last update
  std::vector<double> tangent_p_;   // per local node: the tangent's pressures
  Linearization lin_;
  std::vector<PetscInt> dof_index_;  // per local node: 3 global dof indices (-1 constrained)
  VecHandle patch_sum_;              // ghosted, one value per node
  MatHandle G_, D_, coupling_;       // the g_a by rows, diag(c_a), G^T D G
  std::vector<PetscScalar> g_values_;
  std::vector<PetscInt> g_rows_, g_cols_;                // G's entries: global node, global dof
  std::vector<PetscInt> coupling_rows_, coupling_cols_;  // its entries, in fill order
  std::vector<PetscInt> coupling_row_sizes_;             // per owned row
  MPI_Comm comm_;
};

}  // namespace hs
