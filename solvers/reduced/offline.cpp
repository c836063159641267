#include "solvers/reduced/offline.hpp"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "reduction/ecsw.hpp"
#include "reduction/pod.hpp"

namespace hs {
namespace {

// C of ECSW (reduction/ecsw.hpp): column e holds local tetrahedron e's projected internal
// forces Phi_e^T f_e(Phi Phi^T u_s), stacked over the snapshots s; in a nodal-pressure body
// the elements' columns leave out the volumetric term, which the columns after them hold per
// node patch (`patches`: the nodes in order). The snapshots are projected first, so that the
// weights are fit on the states the reduced model can reach.
Eigen::MatrixXd element_contributions(const Problem& problem, const Eigen::MatrixXd& phi,
                                      const Eigen::MatrixXd& training,
                                      const std::vector<int32_t>& patches) {
  const Distribution& dist = problem.distribution();
  const int k = static_cast<int>(phi.cols()), npe = dist.nodes_per_tet(), n = 3 * npe;
  const int64_t tets = static_cast<int64_t>(dist.local_tets.size());
  const NodalPressure* nodal = problem.nodal_pressure();
  const std::vector<std::vector<int64_t>> patch_tets =
      nodal ? nodal->patch_elements() : std::vector<std::vector<int64_t>>{};
  Eigen::MatrixXd C(k * training.cols(), tets + static_cast<Eigen::Index>(patches.size()));
  double re[30];
  std::vector<double> grad;
  auto rows_of = [&](int64_t e) {
    Eigen::MatrixXd P(n, k);
    for (int a = 0; a < npe; ++a)
      P.middleRows(3 * a, 3) = phi.middleRows(3 * dist.tet_nodes[e * npe + a], 3);
    return P;
  };
  for (Eigen::Index s = 0; s < training.cols(); ++s) {
    const Eigen::VectorXd u = phi * (phi.transpose() * training.col(s));
    for (int64_t e = 0; e < tets; ++e) {
      const ElementOutput out = problem.element_force(e, u.data(), re, nullptr, false);
      if (!out.valid)
        throw SolveError("hydrosoft reduce: a projected snapshot inverts element " +
                         std::to_string(dist.local_tets[e]) + "; more modes are needed");
      C.block(s * k, e, k, 1) = rows_of(e).transpose() * Eigen::Map<const Eigen::VectorXd>(re, n);
    }
    for (size_t i = 0; i < patches.size(); ++i) {
      const std::vector<int64_t>& around = patch_tets[patches[i]];
      grad.resize(12 * around.size());
      NodalPressure::PatchTerm term;
      if (!nodal->patch_term(patches[i], around, u.data(), term, grad.data(), nullptr))
        throw SolveError("hydrosoft reduce: a projected snapshot inverts the patch of node " +
                         std::to_string(dist.old_of_local[patches[i]]) + "; more modes are needed");
      Eigen::VectorXd f = Eigen::VectorXd::Zero(k);
      for (size_t j = 0; j < around.size(); ++j)
        f += rows_of(around[j]).transpose() * Eigen::Map<const Eigen::VectorXd>(&grad[12 * j], 12);
      C.block(s * k, tets + static_cast<Eigen::Index>(i), k, 1) = term.p / 4 * f;
    }
  }
  return C;
}

// ECSW's rows (k a snapshot) are kept to this many: its matrix is rows x tetrahedra, and the
// pendulum's 609 training snapshots of its four actuators' grid (18,000 rows) had not been
// fit after three minutes and 1.7 GB. Beyond it, evenly spaced snapshots (the first, the rest
// state, and the last among them) stand for all; the held-back check measures the result.
constexpr Eigen::Index kMaxEcswRows = 2000;

Eigen::MatrixXd ecsw_snapshots(const Eigen::MatrixXd& training, Eigen::Index k) {
  const Eigen::Index n = training.cols(), used = std::clamp<Eigen::Index>(kMaxEcswRows / k, 2, n);
  if (used == n) return training;
  Eigen::MatrixXd subset(training.rows(), used);
  for (Eigen::Index i = 0; i < used; ++i)
    subset.col(i) = training.col(
        static_cast<Eigen::Index>(std::llround(static_cast<double>(i) * (n - 1) / (used - 1))));
  return subset;
}

}  // namespace

void build_reduced_model(const Problem& problem, const Eigen::MatrixXd& training,
                         const TrainingConfig& settings, ReducedModel& model) {
  const Distribution& dist = problem.distribution();
  double t0 = MPI_Wtime();
  const PodBasis pod = pod_basis(training, settings.energy_tolerance, settings.max_modes);
  const Eigen::MatrixXd& phi = pod.modes;
  model.basis.resize(phi.rows(), phi.cols());
  for (int64_t n = 0; n < dist.num_local(); ++n)
    model.basis.middleRows(3 * dist.old_of_local[n], 3) = phi.middleRows(3 * n, 3);
  std::vector<double> sigma(pod.singular_values.data(),
                            pod.singular_values.data() + pod.singular_values.size());
  model.report["pod"] = {{"snapshots", training.cols()},
                         {"modes", phi.cols()},
                         {"energy_tolerance", settings.energy_tolerance},
                         {"discarded_energy", pod.discarded_energy},
                         {"singular_values", sigma},
                         {"seconds", MPI_Wtime() - t0}};
  t0 = MPI_Wtime();
  const Eigen::MatrixXd snapshots = ecsw_snapshots(training, phi.cols());
  std::vector<int32_t> patches;  // the nodes whose patch terms ECSW may sample
  if (const NodalPressure* nodal = problem.nodal_pressure()) {
    const std::vector<std::vector<int64_t>> around = nodal->patch_elements();
    for (size_t a = 0; a < around.size(); ++a)
      if (!around[a].empty()) patches.push_back(static_cast<int32_t>(a));
  }
  const Eigen::MatrixXd C = element_contributions(problem, phi, snapshots, patches);
  const Eigen::VectorXd b = C.rowwise().sum();
  const EcswWeights w =
      ecsw_weights(C, b, settings.ecsw_tolerance, [] { return interrupt_signal() != 0; });
  if (w.interrupted) throw Interrupted(interrupt_signal());
  if (w.elements.empty()) throw SolveError("hydrosoft reduce: ECSW kept no element");
  const int64_t tets = static_cast<int64_t>(dist.local_tets.size());
  model.elements.clear();
  model.weights.clear();
  model.patches.clear();
  model.patch_weights.clear();
  for (size_t i = 0; i < w.elements.size(); ++i) {
    if (w.elements[i] < tets) {
      model.elements.push_back(dist.local_tets[w.elements[i]]);
      model.weights.push_back(w.weights[i]);
    } else {
      model.patches.push_back(dist.old_of_local[patches[w.elements[i] - tets]]);
      model.patch_weights.push_back(w.weights[i]);
    }
  }
  if (!w.converged)  // built on one rank
    std::cerr << "hydrosoft: warning: ECSW's tolerance " << settings.ecsw_tolerance
              << " was not met (" << w.reason << "): the model keeps " << w.elements.size()
              << " elements and patches at a relative residual of " << w.relative_residual
              << ", and the held-back samples measure its error; --ecsw-tolerance chooses\n";
  model.report["ecsw"] = {
      {"elements", model.elements.size()},
      {"of", dist.local_tets.size()},
      {"patches", model.patches.size()},
      {"of_patches", patches.size()},
      {"snapshots", snapshots.cols()},
      {"tolerance", settings.ecsw_tolerance},
      {"relative_residual", w.relative_residual},
      {"converged", w.converged},
      {"reason", w.converged ? nlohmann::json(nullptr) : nlohmann::json(w.reason)},
      {"seconds", MPI_Wtime() - t0}};
}

}  // namespace hs
