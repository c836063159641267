// `hydrosoft reduce DECK -o MODEL.h5` (docs/reduced_models.md): a control deck's states (the
// rest state), then the full model's equilibrium at samples of the actuation space (phase 1,
// one planned step and one progress line per snapshot), then the reduced model built from
// them (offline.hpp), checked on the held-back samples and written. The samples are a design
// over every actuator's [min, max] range (reduction/design.hpp: a grid, or a space-filling
// design for many actuators), walked so that each solve starts from a neighbour, some of them
// held back. The full solves run on every rank of the run; the model is built on one
// (whole_body.hpp).
#pragma once

#include <memory>

#include "solvers/effectors.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/stepping/states_stepper.hpp"

namespace hs {

struct ReducedModel;

class TrainingStepper : public Stepper {
 public:
  // Collective. Throws InputError naming the deck when it cannot be reduced.
  TrainingStepper(const Config& config, Problem& problem, ConstraintSet& constraints,
                  BorderedNewton& newton, SteppingStats& stats, const ResultRecorder& recorder);

  int phase() const override { return states_.done() ? 1 : 0; }
  int planned_steps() const override;
  bool done() const override { return states_.done() && built_; }
  std::optional<StepReport> advance(Vec u) override;

  nlohmann::json position() const override { return states_.position(); }
  NamedVecs checkpoint_fields(Vec u) const override { return states_.checkpoint_fields(u); }
  void resume(const Restart& restart, Vec u) override;

  int newton_iterations() const override { return stats_.newton_iterations + iterations_; }
  // summary.json's `states` and `reduction` (the training's report).
  void add_summary(nlohmann::json& summary) const override;

 private:
  // The model from the snapshots, its check on the held-back samples, the file; on several
  // ranks, on rank 0's copy of the whole body.
  void build();
  nlohmann::json build_on(Problem& problem, ConstraintSet& constraints, const Effectors& effectors,
                          const std::vector<Eigen::VectorXd>& snapshots);
  nlohmann::json build_on_rank_zero();
  void check_held_back(Problem& problem, ConstraintSet& constraints, const Effectors& effectors,
                       const std::vector<Eigen::VectorXd>& snapshots, const std::vector<int>& check,
                       ReducedModel& model);

  const Config& config_;
  Problem& problem_;
  ConstraintSet& constraints_;
  const SteppingStats& stats_;
  StatesStepper states_;
  Effectors effectors_;
  InverseController controller_;
  // The design's samples (actuations, in the order solved), made when the rest state is
  // known (where a space-filling design's walk starts).
  void plan();
  size_t planned_samples_ = 0;
  std::vector<std::vector<double>> samples_;
  std::vector<bool> held_back_;
  size_t next_ = 0;
  std::vector<Eigen::VectorXd> snapshots_;      // local dofs: the rest state, then each sample
  std::vector<std::vector<double>> positions_;  // the effectors' at each snapshot
  int iterations_ = 0;
  bool started_ = false, built_ = false;
  double t_start_ = 0, snapshot_seconds_ = 0;
  nlohmann::json report_;
};

}  // namespace hs
