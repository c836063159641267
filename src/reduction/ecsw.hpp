// Energy-conserving sampling and weighting (ECSW; docs/reduced_models.md): the hyper-reduction
// of a reduced model's internal forces. Column e of C holds element e's projected internal
// forces over the training snapshots (Phi_e^T f_e(u_s), stacked over s), b = C 1 their sum over
// all elements. ECSW finds few elements and positive weights w, C w ~ b, by non-negative least
// squares stopped as soon as
//   |C w - b| <= tolerance |b|,
// the Lawson-Hanson active-set method whose outer loop adds one element at a time (the one
// whose weight would lower the residual most), so that the weights stay sparse. Positive
// weights keep the reduced tangent a sum of element tangents: symmetric, and positive
// definite where theirs are. Pure: Eigen only.
//
// A fit keeps at most a quarter of C's rows, or 256 elements where that is more: one element
// a row always meets the tolerance (a basic solution), but each addition costs more than the
// last, and a tolerance the residual approaches slowly took minutes (`reason` says where it
// stopped).
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

namespace hs {

struct EcswWeights {
  std::vector<int> elements;     // the columns of C kept, ascending
  std::vector<double> weights;   // > 0, one per element kept
  double relative_residual = 0;  // |C w - b| / |b| reached
  bool converged = false;        // the tolerance was met
  bool interrupted = false;      // `interrupted` said so: the weights are not a fit
  std::string
      reason;  // why not converged: out of reach (then how far it was fit), or no column lowers it
};

// Throws std::invalid_argument when sizes disagree, data is not finite or the tolerance is
// not in (0, 1). A zero b needs no element. `interrupted`, asked once per element added,
// stops the fit (a signal).
EcswWeights ecsw_weights(const Eigen::MatrixXd& C, const Eigen::VectorXd& b, double tolerance,
                         const std::function<bool()>& interrupted = {});

}  // namespace hs
