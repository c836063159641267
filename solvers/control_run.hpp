// The control loop of a deck with a `control` section (docs/control.md): after the deck's
// states (the rest state), every target set gets control.steps_per_target steps of the
// inverse controller; its result (target, reached position, error, actuation, saturated
// actuators) goes to summary.json's `targets`, the step times to `step_time_ms`. Targets
// come from the deck or, with `--targets -`, from standard input (the interactive mode): one
// line each ("x y z" for the first effector, or "effector x y z"), and every line gets one
// JSON line at once on standard output, its answer or why it was refused; a bad line does
// not end the run, only the end of the input does. A batch run checkpoints at target-set
// boundaries and continues from one (docs/control.md, "Checkpoints and restarts").
#pragma once

#include <array>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "solvers/interactive_io.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/output/result_recorder.hpp"
#include "solvers/reduced/reduced_controller.hpp"
#include "solvers/stepping/boundary_moves.hpp"

namespace hs {

// Built before any work, so that a bad effector (outside the mesh, a point group without
// exactly one node), actuator (a sealed chamber, an unknown cavity) or deck target (too far
// from the body to be answered) stops the run first.
class ControlLoop {
 public:
  ControlLoop(const Config& config, Problem& problem, ConstraintSet& constraints,
              BorderedNewton& newton, InteractiveIo io = {});

  // From configuration u at the end of the states (the rest state), unless resume() put the
  // loop at a checkpoint's target set.
  void start(Vec u);
  // The deck's target sets (0 in the interactive mode: not known ahead), and those done.
  int planned_sets() const;
  int sets_done() const { return totals_.sets; }
  bool done() const;
  // Collective: steps towards the next target set (control.steps_per_target steps of the
  // controller): the deck's next, or the next line of the interactive input that is answered
  // (a refused line gets its error line at once and changes nothing). False at the end of the
  // input, or when a signal came while it waited (then it throws Interrupted).
  bool next_set(Vec u);
  // The progress line's words for the last target set: its number and largest error.
  std::string progress_text() const;
  // The last target set is to be written as output step `step` (-1: not written): its
  // entries of `targets` take it, and in the interactive mode its answer goes out. Called
  // again for a set already answered (a set written at the end of the run, or when a signal
  // stops it), it numbers the set's entries only.
  void answer(int step);

  // Checkpoints at a target-set boundary (a batch run only): the position, holding `states`
  // (summary.json's, so far), and the vectors.
  nlohmann::json position(const nlohmann::json& states) const;
  NamedVecs checkpoint_fields(Vec u) const;
  // Whether a checkpoint was written by the control loop (else by the states before it).
  static bool resumes(const Restart& restart);
  // Collective: puts back u, the constraints, the controller and the results so far from a
  // checkpoint of the control loop; returns the summary's `states` of the run it came from.
  nlohmann::json resume(const Restart& restart, Vec u);

  // The summary keys `targets`, `step_time_ms`, `qp`, and in the interactive mode `input`.
  nlohmann::json summary() const;

  // The target set of one interactive line; throws InputError with the reason (the line is
  // named by the caller): the words (parse_target_words), an unknown effector, or a target
  // too far from the body (target_reach_problem).
  std::vector<ControlTarget> targets_of_line(const std::string& line) const;

  // Collective: the history's columns at u (docs/output.md): effector_<name>_x_m, _y_m, _z_m
  // per effector, and per actuator its actuation, actuator_<name>_Pa (a cavity's pressure)
  // or actuator_<name>_N (a cable's tension).
  void add_history(Vec u, HistoryRow& row) const;
  // The control steps' Newton iterations so far.
  int newton_iterations() const { return newton_iterations_; }
  // The summary's `targets` entries of the target sets finished so far: what a failed or
  // stopped run keeps in its .failed summary.json.
  const nlohmann::json& targets_so_far() const { return totals_.targets; }

 private:
  void check_reach(const ControlTarget& target) const;
  // The steps towards one target set, their times and counts in totals_, and the entries of
  // `targets` that wait for their output step (answer()).
  void reach(Vec u, const std::vector<ControlTarget>& targets, int line_number);
  ControlStepReport take_steps(Vec u, const std::vector<ControlTarget>& targets, bool& limit_point);
  // The interactive mode: reach() for one line; a step that fails (SolveError) puts u and the
  // constraints back, writes the line's error line and returns false.
  bool reach_or_explain(Vec u, const std::vector<ControlTarget>& targets, int line_number);
  // Throws SolveError unless the answer's numbers and the fields its output step writes are
  // finite on every rank.
  void check_finite(Vec u, const ControlStepReport& r,
                    const std::vector<double>& equilibrium) const;
  // The interactive mode's next answered line, or false at the end of its input.
  bool next_line_answered(Vec u);
  // Rank 0's JSON line on the interactive output; the first that cannot be written ends the
  // session.
  void write_line(const std::string& text);

  // What the loop keeps between target sets for summary.json: the entries of `targets` and
  // the steps' times so far (a checkpoint holds it: the statistics cover the whole run).
  struct Totals {
    nlohmann::json targets = nlohmann::json::array();
    std::vector<double> total;  // each step's time and its parts (ms)
    std::map<std::string, std::vector<double>> parts;
    double kkt_max = 0;
    int unsolved = 0, sets = 0;
    // control.factor_threads > 0: per step, the staleness of the preconditioning
    // factorization and the correction's iterations; the background factorizations that
    // failed.
    std::vector<int> staleness, iterations;
    nlohmann::json failures = nlohmann::json::array();
  };
  nlohmann::json totals_state() const;
  // The interactive session: its lines read, refused and how it ended.
  struct Session {
    int lines = 0, rejected = 0;
    int failed = 0;       // lines whose control step failed (answered by an error line)
    int undelivered = 0;  // rank 0's JSON lines that could not be written
    std::string kept;     // the last line's first kTargetLineKept characters
    std::size_t length = 0;
    int end = 0;             // none, end of input, output closed
    nlohmann::json summary;  // summary.json's `input`, once it ended
  };

  const Config& config_;
  Problem& problem_;
  ConstraintSet& constraints_;
  int newton_iterations_ = 0;
  Effectors effectors_;
  InverseController controller_;
  std::unique_ptr<ReducedController> reduced_;  // control.reduced_model
  InteractiveIo io_;
  Totals totals_;
  BoundaryMoves moves_;   // the present target set's `move`, ramped over its steps
  VecHandle moved_from_;  // while moves_ act: the answer before the last (predict_move)
  void predict_move(Vec u, double tau0, double tau1);
  Session session_;
  nlohmann::json pending_ = nlohmann::json::array();  // the last set's entries, unanswered
  size_t last_set_entries_ = 0;                       // the last answered set's in targets
  int pending_line_ = 0;                              // their input line (interactive)
  bool resumed_ = false, interactive_ = false;
  std::array<double, 3> body_low_{}, body_high_{};  // the mesh's bounding box (reference)
};

}  // namespace hs
