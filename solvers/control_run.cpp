#include "solvers/control_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>

#include "common/error.hpp"
#include "common/interrupt.hpp"
#include "control/target_line.hpp"
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

// One line of the interactive input: its number (from 1), its first kTargetLineKept
// characters and its whole length.
struct InputLine {
  int number = 0;
  std::string kept;
  std::size_t length = 0;
};

// Why the interactive session ended.
enum class InputEnd { none, end_of_input, output_closed };

// Reads the next line on rank 0 and shares it with every rank; false on every rank at the
// end of the input, or when rank 0 could no longer write its answers (`closed`), with the
// reason in `end`.
bool next_line(std::istream& in, MPI_Comm comm, bool closed, InputLine& line, InputEnd& end) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int more = static_cast<int>(closed ? InputEnd::output_closed : InputEnd::end_of_input);
  unsigned long length = 0;
  if (rank == 0 && !closed && read_target_line(in, kTargetLineKept, line.kept, line.length)) {
    more = static_cast<int>(InputEnd::none);
    ++line.number;
    length = line.length;
  }
  MPI_Bcast(&more, 1, MPI_INT, 0, comm);
  end = static_cast<InputEnd>(more);
  if (end != InputEnd::none) return false;
  MPI_Bcast(&line.number, 1, MPI_INT, 0, comm);
  MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG, 0, comm);
  line.length = length;
  int n = static_cast<int>(line.kept.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, comm);
  line.kept.resize(n);
  MPI_Bcast(line.kept.data(), n, MPI_CHAR, 0, comm);
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
      io_(std::move(io)) {
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
      row.add("effector_" + effectors_.name(e) + "_" + "xyz"[d] + "_m", x[3 * e + d]);
  for (const auto& actuator : config_.control->actuators) {
    const Constraint& c = constraints_[constraints_.find(actuator.constraint)];
    row.add("actuator_" + c.name() + (c.is_cavity() ? "_Pa" : "_N"), c.lambda);
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

nlohmann::json ControlLoop::run(Vec u, ResultRecorder& recorder, double first_time,
                                Checkpointer* checkpoints, const nlohmann::json& states) {
  const Config& config = config_;
  Effectors& effectors = effectors_;
  InverseController& controller = controller_;
  const bool interactive = config.control->targets_from_stdin;
  int rank = 0;
  MPI_Comm_rank(problem_.comm(), &rank);
  if (!resumed_) controller.set_rest(u);
  if (checkpoints) checkpoints->start_count();

  nlohmann::json out;
  Totals& t = totals_;
  for (const auto& part : ControlStepReport{}.parts()) t.parts[part.first];  // even without steps
  const bool background = config.control->factor_threads > 0;
  // Rank 0's JSON lines that could not be written: the first ends the session.
  int undelivered = 0;
  auto write_line = [&](const std::string& text) {
    if (undelivered == 0 && io_.write_line(text)) return;
    if (undelivered++ == 0)
      std::cerr << "hydrosoft: standard output is closed (the client is gone): the session "
                   "ends; the answer to its last line was not delivered"
                << std::endl;
  };
  // Steps towards one target set, its output step, and its entries in `targets` (answered at
  // once on the interactive output, with the number of its input line).
  auto reach = [&](const std::vector<ControlTarget>& targets, int line_number) {
    ControlStepReport r;
    bool limit_point = false;
    for (int k = 0; k < config.control->steps_per_target; ++k) {
      r = controller.step(u, targets);
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
    // With the free configuration converged by Newton, the reported position is the
    // equilibrium at the final actuation, not the last step's linear prediction (the same
    // when newton_finish is on). The one_step mode never waits for Newton: it reports the
    // prediction, and the next step's residual corrects it.
    if (config.control->free_solve == FreeSolve::newton) {
      controller.settle(u, r);
      limit_point |= r.limit_point;
    }
    std::vector<double> equilibrium;
    if (config.control->free_solve == FreeSolve::one_step && config.control->check_equilibrium)
      equilibrium = controller.equilibrium_positions(u);
    recorder.record(first_time + ++t.sets, u, 1.0, "target_set");
    auto error_of = [&](const std::vector<double>& x, int e, const ControlTarget& target) {
      double err2 = 0;
      for (int d = 0; d < 3; ++d)
        if (effectors.config(e).directions[d])
          err2 += std::pow(x[3 * e + d] - target.position[d], 2);
      return std::sqrt(err2);
    };
    for (const auto& target : targets) {
      const int e = effectors.index(target.effector);
      nlohmann::json j;
      j["effector"] = target.effector;
      j["target"] = target.position;
      j["reached"] = {r.reached[3 * e], r.reached[3 * e + 1], r.reached[3 * e + 2]};
      j["error_m"] = error_of(r.reached, e, target);
      if (!equilibrium.empty()) {
        j["equilibrium"] = {equilibrium[3 * e], equilibrium[3 * e + 1], equilibrium[3 * e + 2]};
        j["equilibrium_error_m"] = error_of(equilibrium, e, target);
      }
      j["step_ms"] = r.total_ms;
      if (background) {
        j["staleness"] = r.staleness;
        j["correction_iterations"] = r.correction_iterations;
      }
      j["actuation"] = r.actuation;
      j["saturated"] = r.saturated;
      j["limit_point"] = limit_point;
      j["step"] = recorder.written() - 1;
      if (interactive && rank == 0) write_line(json_line({{"answer", j}, {"line", line_number}}));
      if (interactive) j["line"] = line_number;
      t.targets.push_back(j);
    }
  };

  if (!interactive) {
    const auto& sets = config.control->targets;
    Progress progress(config.output.progress, problem_.comm(), static_cast<int>(sets.size()));
    for (size_t k = t.sets; k < sets.size(); ++k) {
      reach(sets[k], 0);
      double worst = 0;  // over the set's effectors
      for (size_t i = t.targets.size() - sets[k].size(); i < t.targets.size(); ++i)
        worst = std::max(worst, t.targets[i]["error_m"].get<double>());
      char what[64];
      std::snprintf(what, sizeof what, "target set %zu  error %.3f mm", k + 1, 1e3 * worst);
      progress.step(static_cast<int>(k + 1), what, newton_iterations_);
      // A signal stops the run here, after the target set's output step (and checkpoint).
      const int signal = interrupt_requested(problem_.comm());
      if (checkpoints && checkpoints->due(signal)) {
        NamedVecs fields{{"displacement", u}};
        for (const auto& field : controller.checkpoint_fields()) fields.push_back(field);
        checkpoints->write({{"target_set", k + 1},
                            {"last", k + 1 == sets.size()},
                            {"constraints", constraint_states(constraints_)},
                            {"states", states},
                            {"controller", controller.checkpoint_state()},
                            {"loop", totals_state()}},
                           fields);
      }
      if (signal) throw Interrupted(signal);
    }
  } else {
    // Every line gets exactly one JSON line: its answer, or why it was refused. A refused
    // line changes nothing (no step, no output step), and the next line is read.
    InputLine line;
    InputEnd end = InputEnd::none;
    int rejected = 0;
    // A signal stops the reading between lines. One that comes while rank 0 waits for a line
    // interrupts the read (the handler does not restart it), which ends the input: the check
    // after the loop then stops the run. A closed standard output ends the session as the
    // end of the input does: every step so far converged, and the results are kept as any
    // run's (docs/control.md, "Interactive use").
    while (!interrupt_requested(problem_.comm()) &&
           next_line(*io_.input, problem_.comm(), undelivered > 0, line, end)) {
      std::vector<ControlTarget> targets;
      std::string error;
      try {
        if (line.length > line.kept.size())
          throw InputError("line too long (a target line has at most " +
                           std::to_string(kTargetLineKept) + " characters)");
        targets = targets_of_line(line.kept);
      } catch (const InputError& e) {
        error = std::string(e.what()) + ": " + quote_target_line(line.kept, line.length);
      }
      if (error.empty()) {
        reach(targets, line.number);
        continue;
      }
      ++rejected;
      if (rank == 0) {
        write_line(json_line({{"error", error}, {"line", line.number}}));
        std::cerr << "hydrosoft: standard input, line " << line.number << " refused: " << error
                  << std::endl;
      }
    }
    stop_if_interrupted(problem_.comm());
    MPI_Bcast(&undelivered, 1, MPI_INT, 0, problem_.comm());
    out["input"] = {
        {"lines", line.number},
        {"answered", line.number - rejected},
        {"rejected", rejected},
        {"end", end == InputEnd::output_closed ? "standard output closed" : "end of input"},
        {"undelivered", undelivered}};
  }
  auto timing = [](const std::vector<double>& v) {
    double sum = 0;
    for (double x : v) sum += x;
    return nlohmann::json{{"median", percentile(v, 0.5)},
                          {"mean", v.empty() ? 0.0 : sum / v.size()},
                          {"p95", percentile(v, 0.95)},
                          {"max", percentile(v, 1.0)}};
  };
  out["targets"] = t.targets;
  out["step_time_ms"] = timing(t.total);
  for (const auto& [name, v] : t.parts)
    out["step_time_ms"]["split_median"][name] = percentile(v, 0.5);
  out["step_time_ms"]["steps"] = t.total.size();
  out["qp"] = {{"kkt_residual_max", t.kkt_max}, {"unsolved", t.unsolved}};
  if (background)
    out["background_factorization"] = {{"threads", config.control->factor_threads},
                                       {"step_ms", t.total},
                                       {"staleness", t.staleness},
                                       {"correction_iterations", t.iterations},
                                       {"failures", t.failures}};
  return out;
}

}  // namespace hs
