#include "solvers/control_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "control/target_line.hpp"
#include "solvers/output/result_recorder.hpp"
#include "solvers/progress.hpp"

namespace hs {
namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const double pos = q * (v.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos)), hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - lo) * (v[hi] - v[lo]);
}

// Why the interactive session ended.
enum class InputEnd { none, end_of_input, output_closed };

// Reads the next line on rank 0 and shares it with every rank (its number from 1, its first
// kTargetLineKept characters and its whole length); false on every rank at the end of the
// input, or when rank 0 could no longer write its answers (`closed`), with the reason in `end`.
bool next_line(std::istream& in, MPI_Comm comm, bool closed, int& number, std::string& kept,
               std::size_t& line_length, int& end) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int more = static_cast<int>(closed ? InputEnd::output_closed : InputEnd::end_of_input);
  unsigned long length = 0;
  if (rank == 0 && !closed && read_target_line(in, kTargetLineKept, kept, line_length)) {
    more = static_cast<int>(InputEnd::none);
    ++number;
    length = line_length;
  }
  MPI_Bcast(&more, 1, MPI_INT, 0, comm);
  end = more;
  if (static_cast<InputEnd>(end) != InputEnd::none) return false;
  MPI_Bcast(&number, 1, MPI_INT, 0, comm);
  MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG, 0, comm);
  line_length = length;
  int n = static_cast<int>(kept.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, comm);
  kept.resize(n);
  MPI_Bcast(kept.data(), n, MPI_CHAR, 0, comm);
  return true;
}

// One JSON line; bytes that are not UTF-8 (a client's garbage, quoted in a message) become
// U+FFFD instead of stopping the run.
std::string json_line(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace

ControlLoop::ControlLoop(const Config& config, Problem& problem, ConstraintSet& constraints,
                         BorderedNewton& newton, InteractiveIo io)
    : config_(config),
      problem_(problem),
      constraints_(constraints),
      effectors_(config, problem),
      controller_(config, problem, constraints, newton, effectors_),
      io_(std::move(io)),
      interactive_(config.control->targets_from_stdin) {
  if (!config.control->reduced_model.empty())
    reduced_ = std::make_unique<ReducedController>(config, problem, constraints, effectors_);
  if (!io_.input) io_.input = &std::cin;
  if (!io_.write_line)
    io_.write_line = [](const std::string& line) {
      std::cout << line << std::endl;
      return static_cast<bool>(std::cout);
    };
  const std::vector<double>& x = problem.distribution().x;
  body_low_.fill(HUGE_VAL);
  body_high_.fill(-HUGE_VAL);
  for (size_t i = 0; i < x.size(); ++i) {
    body_low_[i % 3] = std::min(body_low_[i % 3], x[i]);
    body_high_[i % 3] = std::max(body_high_[i % 3], x[i]);
  }
  MPI_Allreduce(MPI_IN_PLACE, body_low_.data(), 3, MPI_DOUBLE, MPI_MIN, problem.comm());
  MPI_Allreduce(MPI_IN_PLACE, body_high_.data(), 3, MPI_DOUBLE, MPI_MAX, problem.comm());
  const auto& sets = config.control->targets;
  for (size_t k = 0; k < sets.size(); ++k)
    for (const auto& t : sets[k]) {
      try {
        check_reach(t);
      } catch (const InputError& e) {
        throw InputError(config.deck_path + ": control.targets[" + std::to_string(k) + "]." +
                         t.effector + ": " + e.what());
      }
    }
}

void ControlLoop::check_reach(const ControlTarget& target) const {
  const int e = effectors_.index(target.effector);
  if (e >= 0 && effectors_.is_force(e)) return;  // a force: any value can be asked
  const std::string problem = target_reach_problem(target.position, body_low_, body_high_);
  if (!problem.empty()) throw InputError(problem);
}

std::vector<ControlTarget> ControlLoop::targets_of_line(const std::string& line) const {
  const TargetWords words = parse_target_words(line);
  ControlTarget t;
  t.effector = words.effector.empty() ? effectors_.name(0) : words.effector;
  t.position = words.position;
  if (effectors_.index(t.effector) < 0)
    throw InputError("no effector named " + quote_target_line(t.effector, t.effector.size()));
  check_reach(t);
  return {t};
}

void ControlLoop::add_history(Vec u, HistoryRow& row) const {
  const std::vector<double> x = effectors_.positions(u);
  for (int e = 0; e < effectors_.size(); ++e)
    for (int d = 0; d < 3; ++d)
      row.add("effector_" + effectors_.name(e) + "_" + "xyz"[d] + "_" + effectors_.unit(e),
              x[3 * e + d]);
  for (const auto& actuator : config_.control->actuators) {
    const Constraint& c = constraints_[constraints_.find(actuator.constraint)];
    row.add("actuator_" + c.name() + "_" + c.units().multiplier, c.multiplier());
  }
}

bool ControlLoop::resumes(const Restart& restart) {
  return restart.position().contains("target_set");
}

nlohmann::json ControlLoop::totals_state() const {
  return {{"targets", totals_.targets},     {"step_ms", totals_.total},
          {"parts_ms", totals_.parts},      {"kkt_residual_max", totals_.kkt_max},
          {"unsolved", totals_.unsolved},   {"sets", totals_.sets},
          {"staleness", totals_.staleness}, {"correction_iterations", totals_.iterations},
          {"failures", totals_.failures},   {"newton_iterations", newton_iterations_}};
}

nlohmann::json ControlLoop::resume(const Restart& restart, Vec u) {
  if (reduced_)
    throw InputError(
        "--restart: a run with control.reduced_model starts afresh (its answers "
        "take milliseconds; docs/reduced_models.md)");
  const nlohmann::json& p = restart.position();
  restart.read("displacement", problem_, u);
  restore_constraint_states(constraints_, p.at("constraints"));
  controller_.resume(p.at("controller"), restart);
  const nlohmann::json& t = p.at("loop");
  totals_.targets = t.at("targets");
  for (auto& entry : totals_.targets) entry["step"] = nullptr;  // in the earlier run's .h5
  totals_.total = t.at("step_ms").get<std::vector<double>>();
  totals_.parts = t.at("parts_ms").get<std::map<std::string, std::vector<double>>>();
  totals_.kkt_max = t.at("kkt_residual_max");
  totals_.unsolved = t.at("unsolved");
  totals_.sets = t.at("sets");
  totals_.staleness = t.at("staleness").get<std::vector<int>>();
  totals_.iterations = t.at("correction_iterations").get<std::vector<int>>();
  totals_.failures = t.at("failures");
  newton_iterations_ = t.at("newton_iterations");
  if (totals_.sets != p.at("target_set").get<int>() ||
      totals_.sets > static_cast<int>(config_.control->targets.size()))
    throw InputError("--restart: the checkpoint's target set " + std::to_string(totals_.sets) +
                     " is not one of this deck's");
  resumed_ = true;
  nlohmann::json states = p.at("states");
  for (auto& state : states) state["step"] = nullptr;
  return states;
}

void ControlLoop::start(Vec u) {
  // Friction's lag is the rest state's until the first control step ends, then each step's
  // end: the controller's trial and check solves do not move it (docs/contact.md,
  // "Friction").
  problem_.take_friction_lag(u, 1.0);
  problem_.hold_friction_lag(true);
  if (!resumed_) controller_.set_rest(u);
  if (reduced_) reduced_->set_rest(u);
  for (const auto& part : ControlStepReport{}.parts())
    totals_.parts[part.first];  // even without steps
}

int ControlLoop::planned_sets() const {
  return interactive_ ? 0 : static_cast<int>(config_.control->targets.size());
}

bool ControlLoop::done() const {
  if (interactive_) return !session_.summary.is_null();
  return totals_.sets == static_cast<int>(config_.control->targets.size());
}

bool ControlLoop::next_set(Vec u) {
  if (interactive_) return next_line_answered(u);
  const size_t k = totals_.sets;
  const auto& moves = config_.control->moves;
  moves_ = k < moves.size() ? BoundaryMoves(moves[k]) : BoundaryMoves();
  moves_.begin(problem_);
  reach(u, config_.control->targets[k], 0);
  moves_ = BoundaryMoves();
  return true;
}

ControlStepReport ControlLoop::take_steps(Vec u, const std::vector<ControlTarget>& targets,
                                          bool& limit_point) {
  int rank = 0;
  MPI_Comm_rank(problem_.comm(), &rank);
  Totals& t = totals_;
  ControlStepReport r;
  const int steps = config_.control->steps_per_target;
  for (int k = 0; k < steps; ++k) {
    moves_.set(problem_, static_cast<double>(k + 1) / steps);
    predict_move(u, static_cast<double>(k) / steps, static_cast<double>(k + 1) / steps);
    r = reduced_ ? reduced_->step(u, targets) : controller_.step(u, targets);
    problem_.take_friction_lag(u, 1.0);  // each step's end the next one's start
    if (!r.fallback.empty() && rank == 0)
      std::cerr << "hydrosoft: control: " << r.fallback << std::endl;
    newton_iterations_ += r.newton_iterations;
    limit_point |= r.limit_point;
    t.total.push_back(r.total_ms);
    for (const auto& [name, ms] : r.parts()) t.parts[name].push_back(ms);
    t.kkt_max = std::max(t.kkt_max, r.kkt_residual);
    t.unsolved += !r.qp_solved;
    t.staleness.push_back(r.staleness);
    t.iterations.push_back(r.correction_iterations);
    if (!r.background_failure.empty()) {
      t.failures.push_back({{"step", t.total.size() - 1}, {"error", r.background_failure}});
      if (rank == 0)
        std::cerr << "hydrosoft: control: " << r.background_failure << "; factored in line"
                  << std::endl;
    }
  }
  return r;
}

// While boundary groups move, each step starts from the last one's answer moved on by that
// answer's own increment (a secant predictor, as the states' steps), and a move's first step
// from the body translated with its one moved group; either only where it keeps every node off
// the obstacles and the contact surfaces. From the answer itself, with the moved values set on
// the boundary alone, Newton met the jump in the elements at the boundary (docs/control.md,
// "Lifting under control").
void ControlLoop::predict_move(Vec u, double tau0, double tau1) {
  if (moves_.empty()) {
    moved_from_.reset();
    return;
  }
  VecHandle step(problem_.create_vector());
  std::array<double, 3> by;
  if (moved_from_) {
    HS_PETSC(VecWAXPY(step, -1.0, moved_from_, u));
  } else {
    // The first step of a move: the body translated with its one moved group, if one.
    HS_PETSC(VecDuplicate(u, moved_from_.out()));
    if (!moves_.one_translation(tau0, tau1, by)) by = {0, 0, 0};
    PetscScalar* a;
    PetscInt n = 0;
    HS_PETSC(VecGetLocalSize(step, &n));
    HS_PETSC(VecGetArray(step, &a));
    for (PetscInt i = 0; i < n; ++i) a[i] = by[i % 3];
    HS_PETSC(VecRestoreArray(step, &a));
  }
  HS_PETSC(VecCopy(u, moved_from_));
  // Not into an obstacle or onto a contact surface: from the answer itself then.
  if (problem_.contact_step_limit(moved_from_, step, 1.0) < 1) return;
  HS_PETSC(VecAXPY(u, 1.0, step));
}

void ControlLoop::reach(Vec u, const std::vector<ControlTarget>& targets, int line_number) {
  bool limit_point = false;
  const double t0 = MPI_Wtime();
  ControlStepReport r = take_steps(u, targets, limit_point);
  // With the free configuration converged by Newton, the reported position is the
  // equilibrium at the final actuation, not the last step's linear prediction (the same
  // when newton_finish is on). The one_step mode never waits for Newton: it reports the
  // prediction, and the next step's residual corrects it.
  if (config_.control->free_solve == FreeSolve::newton && !reduced_) {
    controller_.settle(u, r);
    limit_point |= r.limit_point;
  }
  // The time the line waited for its answer: every step of the set (a reduced model's first
  // step does nearly all the work) and the newton mode's settling, not the check or output.
  // The slowest rank's, as step_ms: every rank's answers are the same (a checkpoint keeps them).
  double answer_ms = 1e3 * (MPI_Wtime() - t0);
  MPI_Allreduce(MPI_IN_PLACE, &answer_ms, 1, MPI_DOUBLE, MPI_MAX, problem_.comm());
  std::vector<double> equilibrium;
  if ((config_.control->free_solve == FreeSolve::one_step || reduced_) &&
      config_.control->check_equilibrium && totals_.sets % config_.control->check_every == 0)
    equilibrium = controller_.equilibrium_positions(u);
  if (io_.after_steps) io_.after_steps(u, line_number);
  check_finite(u, r, equilibrium);
  ++totals_.sets;
  auto error_of = [&](const std::vector<double>& x, int e, const ControlTarget& target) {
    double err2 = 0;
    for (int d = 0; d < 3; ++d)
      if (effectors_.config(e).directions[d])
        err2 += std::pow(x[3 * e + d] - target.position[d], 2);
    return std::sqrt(err2);
  };
  pending_ = nlohmann::json::array();
  pending_line_ = line_number;
  const nlohmann::json contact =  // the obstacles' forces where the set's answer left the body
      problem_.contact() ? contact_json(problem_, u, 1.0) : nlohmann::json();
  for (const auto& target : targets) {
    const int e = effectors_.index(target.effector);
    nlohmann::json j;
    j["effector"] = target.effector;
    j["target"] = target.position;
    j["reached"] = {r.reached[3 * e], r.reached[3 * e + 1], r.reached[3 * e + 2]};
    // In the effector's unit: a contact force's error in N.
    const std::string unit = effectors_.unit(e);
    j["error_" + unit] = error_of(r.reached, e, target);
    if (!equilibrium.empty()) {
      j["equilibrium"] = {equilibrium[3 * e], equilibrium[3 * e + 1], equilibrium[3 * e + 2]};
      j["equilibrium_error_" + unit] = error_of(equilibrium, e, target);
    }
    j["step_ms"] = r.total_ms;
    j["answer_ms"] = answer_ms;
    if (config_.control->factor_threads > 0) {
      j["staleness"] = r.staleness;
      j["correction_iterations"] = r.correction_iterations;
    }
    j["actuation"] = r.actuation;
    if (!r.reduced.is_null()) j["reduced"] = r.reduced;
    if (!r.contact_qp.is_null()) j["contact_qp"] = r.contact_qp;
    j["saturated"] = r.saturated;
    j["limit_point"] = limit_point;
    if (config_.control->free_solve == FreeSolve::one_step) {
      j["refinements"] = r.refinements;
      j["free_step_m"] = r.free_step_m;
      if (effectors_.is_force(e)) j["free_step_N"] = r.free_step_N;
    }
    if (r.negative_pivots >= 0) j["negative_pivots"] = r.negative_pivots;
    if (!contact.is_null()) j["contact"] = contact;
    std::string fallback = r.fallback;
    if (!r.background_failure.empty())
      fallback =
          r.background_failure + "; factored in line" + (fallback.empty() ? "" : "; ") + fallback;
    if (!fallback.empty()) j["fallback"] = fallback;
    pending_.push_back(j);
  }
}

std::string ControlLoop::progress_text() const {
  double worst_m = 0, worst_N = 0;  // over the set's effectors
  for (const auto& entry : pending_) {
    worst_m = std::max(worst_m, entry.value("error_m", 0.0));
    worst_N = std::max(worst_N, entry.value("error_N", 0.0));
  }
  bool forces = false, positions = false;
  for (const auto& entry : pending_) (entry.contains("error_N") ? forces : positions) = true;
  char what[96];
  int n = std::snprintf(what, sizeof what, "target set %zu", static_cast<size_t>(totals_.sets));
  if (positions || !forces)
    n += std::snprintf(what + n, sizeof what - n, "  error %.3f mm", 1e3 * worst_m);
  if (forces) std::snprintf(what + n, sizeof what - n, "  force error %.3g N", worst_N);
  return what;
}

void ControlLoop::answer(int step) {
  if (pending_.empty()) {
    auto& targets = totals_.targets;
    for (size_t i = targets.size() - std::min(last_set_entries_, targets.size());
         i < targets.size(); ++i)
      targets[i]["step"] = step;
    return;
  }
  int rank = 0;
  MPI_Comm_rank(problem_.comm(), &rank);
  last_set_entries_ = pending_.size();
  for (auto& j : pending_) {
    j["step"] = step >= 0 ? nlohmann::json(step) : nlohmann::json(nullptr);
    if (interactive_ && rank == 0) write_line(json_line({{"answer", j}, {"line", pending_line_}}));
    if (interactive_) j["line"] = pending_line_;
    totals_.targets.push_back(j);
  }
  pending_ = nlohmann::json::array();
}

void ControlLoop::write_line(const std::string& text) {
  if (session_.undelivered == 0 && io_.write_line(text)) return;
  if (session_.undelivered++ == 0)
    std::cerr << "hydrosoft: standard output is closed (the client is gone): the session "
                 "ends; the answer to its last line was not delivered"
              << std::endl;
}

// A step that fails (no equilibrium, a factorization that fails, a result that is not finite)
// must not end an interactive session without an answer: the robot is put back where the last
// answered line left it, the line gets an error line, and the session reads the next.
bool ControlLoop::reach_or_explain(Vec u, const std::vector<ControlTarget>& targets,
                                   int line_number) {
  VecHandle saved;
  HS_PETSC(VecDuplicate(u, saved.out()));
  HS_PETSC(VecCopy(u, saved));
  const std::vector<Constraint::State> states = constraints_.snapshot();
  std::string error;
  try {
    reach(u, targets, line_number);
    return true;
  } catch (const Interrupted&) {
    throw;
  } catch (const SolveError& e) {
    error = e.what();
  }
  HS_PETSC(VecCopy(saved, u));
  constraints_.restore(states);
  controller_.recover();
  if (reduced_) reduced_->recover(u);
  pending_ = nlohmann::json::array();
  ++session_.failed;
  const std::string text = "the control step failed (" + error +
                           "): nothing changed, the robot stays where the last answered line "
                           "left it";
  int rank = 0;
  MPI_Comm_rank(problem_.comm(), &rank);
  if (rank == 0) {
    write_line(json_line({{"error", text}, {"line", line_number}}));
    std::cerr << "hydrosoft: standard input, line " << line_number << ": " << text << std::endl;
  }
  return false;
}

// Every number of an answer finite and every element's stress finite, on every rank; else the
// step failed. For the laws whose stress is finite wherever det F > 0 (all but Gent's), every
// element keeping its orientation (J > 0, which a NaN fails too) stands for its stress: the
// whole field's stresses cost more than a reduced model's answer (docs/control.md).
void ControlLoop::check_finite(Vec u, const ControlStepReport& r,
                               const std::vector<double>& equilibrium) const {
  auto finite = [](const std::vector<double>& v) {
    for (double x : v)
      if (!std::isfinite(x)) return false;
    return true;
  };
  int ok = finite(r.reached) && finite(r.actuation) && finite(equilibrium) &&
           std::isfinite(r.free_step_m);
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, problem_.comm());
  bool stress_by_orientation = true;
  for (const auto& m : config_.materials)
    stress_by_orientation &= m.law->finite_wherever_oriented();
  if (ok && stress_by_orientation) {
    ok = problem_.orientation_preserved(u);
  } else if (ok) {
    Problem::ElementFieldValues fields;
    problem_.element_fields(u, fields, false);
    ok = finite(fields.von_mises) && finite(fields.J) && finite(fields.stress) &&
         finite(fields.strain);
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, problem_.comm());
  }
  if (!ok)
    throw SolveError(
        "control step: its result is not finite (a position, an actuation or "
        "the stress of an element)");
}

bool ControlLoop::next_line_answered(Vec u) {
  const MPI_Comm comm = problem_.comm();
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  Session& s = session_;
  // A signal stops the reading between lines. One that comes while rank 0 waits for a line
  // interrupts the read (the handler does not restart it), which ends the input: the check
  // after the loop then stops the run. A closed standard output ends the session as the
  // end of the input does: every step so far converged, and the results are kept as any
  // run's (docs/control.md, "Interactive use").
  while (!interrupt_requested(comm) &&
         next_line(*io_.input, comm, s.undelivered > 0, s.lines, s.kept, s.length, s.end)) {
    std::vector<ControlTarget> targets;
    std::string error;
    try {
      if (s.length > s.kept.size())
        throw InputError("line too long (a target line has at most " +
                         std::to_string(kTargetLineKept) + " characters)");
      targets = targets_of_line(s.kept);
    } catch (const InputError& e) {
      error = std::string(e.what()) + ": " + quote_target_line(s.kept, s.length);
    }
    if (error.empty()) {
      if (reach_or_explain(u, targets, s.lines)) return true;
      continue;  // its error line is written
    }
    // A refused line changes nothing (no step, no output step), and the next line is read.
    ++s.rejected;
    if (rank == 0) {
      write_line(json_line({{"error", error}, {"line", s.lines}}));
      std::cerr << "hydrosoft: standard input, line " << s.lines << " refused: " << error
                << std::endl;
    }
  }
  stop_if_interrupted(comm);
  MPI_Bcast(&s.undelivered, 1, MPI_INT, 0, comm);
  const bool closed = static_cast<InputEnd>(s.end) == InputEnd::output_closed;
  s.summary = {{"lines", s.lines},
               {"answered", s.lines - s.rejected - s.failed},
               {"rejected", s.rejected},
               {"failed", s.failed},
               {"end", closed ? "standard output closed" : "end of input"},
               {"undelivered", s.undelivered}};
  return false;
}

nlohmann::json ControlLoop::position(const nlohmann::json& states) const {
  return {{"target_set", static_cast<size_t>(totals_.sets)},
          {"last", totals_.sets == static_cast<int>(config_.control->targets.size())},
          {"constraints", constraint_states(constraints_)},
          {"states", states},
          {"controller", controller_.checkpoint_state()},
          {"loop", totals_state()}};
}

NamedVecs ControlLoop::checkpoint_fields(Vec u) const {
  NamedVecs fields{{"displacement", u}};
  for (const auto& field : controller_.checkpoint_fields()) fields.push_back(field);
  return fields;
}

nlohmann::json ControlLoop::summary() const {
  const Totals& t = totals_;
  auto timing = [](const std::vector<double>& v) {
    double sum = 0;
    for (double x : v) sum += x;
    return nlohmann::json{{"median", percentile(v, 0.5)},
                          {"mean", v.empty() ? 0.0 : sum / v.size()},
                          {"p95", percentile(v, 0.95)},
                          {"max", percentile(v, 1.0)}};
  };
  nlohmann::json out;
  if (interactive_) out["input"] = session_.summary;
  out["targets"] = t.targets;
  out["step_time_ms"] = timing(t.total);
  for (const auto& [name, v] : t.parts)
    out["step_time_ms"]["split_median"][name] = percentile(v, 0.5);
  out["step_time_ms"]["steps"] = t.total.size();
  out["qp"] = {{"kkt_residual_max", t.kkt_max}, {"unsolved", t.unsolved}};
  if (reduced_) out["reduced_model"] = reduced_->summary();
  if (config_.control->factor_threads > 0)
    out["background_factorization"] = {{"threads", config_.control->factor_threads},
                                       {"step_ms", t.total},
                                       {"staleness", t.staleness},
                                       {"correction_iterations", t.iterations},
                                       {"failures", t.failures}};
  return out;
}

}  // namespace hs
