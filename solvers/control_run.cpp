#include "solvers/control_run.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <sstream>

#include "common/error.hpp"

namespace hs {
namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const double pos = q * (v.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos)), hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - lo) * (v[hi] - v[lo]);
}

// The next target set: from the deck, or a line of standard input read on rank 0 and shared.
class TargetSource {
 public:
  TargetSource(const Config& config, const Effectors& effectors, MPI_Comm comm)
      : config_(config), effectors_(effectors), comm_(comm) {
    MPI_Comm_rank(comm, &rank_);
  }
  bool next(std::vector<ControlTarget>& targets) {
    if (!config_.control->targets_from_stdin) {
      if (index_ >= config_.control->targets.size()) return false;
      targets = config_.control->targets[index_++];
      return true;
    }
    std::string line;
    int more = 0;
    if (rank_ == 0) {
      while (std::getline(std::cin, line)) {
        ++line_number_;
        if (line.find_first_not_of(" \t\r") != std::string::npos) {
          more = 1;
          break;
        }
      }
    }
    MPI_Bcast(&more, 1, MPI_INT, 0, comm_);
    if (!more) return false;
    int n = static_cast<int>(line.size());
    MPI_Bcast(&n, 1, MPI_INT, 0, comm_);
    line.resize(n);
    MPI_Bcast(line.data(), n, MPI_CHAR, 0, comm_);
    MPI_Bcast(&line_number_, 1, MPI_INT, 0, comm_);
    targets = parse_target_line(line, effectors_, line_number_);
    return true;
  }

 private:
  const Config& config_;
  const Effectors& effectors_;
  MPI_Comm comm_;
  int rank_ = 0, line_number_ = 0;
  size_t index_ = 0;
};

}  // namespace

std::vector<ControlTarget> parse_target_line(const std::string& line, const Effectors& effectors,
                                             int line_number) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  const std::string where =
      "standard input, line " + std::to_string(line_number) + " '" + line + "'";
  if (words.size() != 3 && words.size() != 4)
    throw InputError(where + ": expected 'x y z' or 'effector x y z'");
  ControlTarget t;
  t.effector = words.size() == 4 ? words[0] : effectors.name(0);
  if (effectors.index(t.effector) < 0)
    throw InputError(where + ": no effector named '" + t.effector + "'");
  for (int d = 0; d < 3; ++d) {
    const std::string& w = words[words.size() - 3 + d];
    size_t used = 0;
    double x = 0;
    try {
      x = std::stod(w, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != w.size() || !std::isfinite(x))
      throw InputError(where + ": coordinate '" + w + "' is not a finite number");
    t.position[d] = x;
  }
  return {t};
}

ControlLoop::ControlLoop(const Config& config, Problem& problem, ConstraintSet& constraints,
                         BorderedNewton& newton)
    : config_(config),
      problem_(problem),
      effectors_(config, problem),
      controller_(config, problem, constraints, newton, effectors_) {}

nlohmann::json ControlLoop::run(Vec u, ResultRecorder& recorder, double first_time) {
  const Config& config = config_;
  Effectors& effectors = effectors_;
  InverseController& controller = controller_;
  int rank = 0;
  MPI_Comm_rank(problem_.comm(), &rank);
  controller.set_rest(u);
  TargetSource source(config, effectors, problem_.comm());

  nlohmann::json out;
  out["targets"] = nlohmann::json::array();
  // Each step's time and its parts (ms), for the medians of summary.json.
  std::vector<double> total;
  std::map<std::string, std::vector<double>> parts;
  for (const auto& part : ControlStepReport{}.parts()) parts[part.first];  // even without steps
  double kkt_max = 0;
  int unsolved = 0, set = 0;
  std::vector<ControlTarget> targets;
  while (source.next(targets)) {
    ControlStepReport r;
    bool limit_point = false;
    for (int k = 0; k < config.control->steps_per_target; ++k) {
      r = controller.step(u, targets);
      limit_point |= r.limit_point;
      total.push_back(r.total_ms);
      for (const auto& [name, ms] : r.parts()) parts[name].push_back(ms);
      kkt_max = std::max(kkt_max, r.kkt_residual);
      unsolved += !r.qp_solved;
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
    recorder.record(first_time + ++set, u, 1.0);
    auto error_of = [&](const std::vector<double>& x, int e, const ControlTarget& t) {
      double err2 = 0;
      for (int d = 0; d < 3; ++d)
        if (effectors.config(e).directions[d]) err2 += std::pow(x[3 * e + d] - t.position[d], 2);
      return std::sqrt(err2);
    };
    for (const auto& t : targets) {
      const int e = effectors.index(t.effector);
      nlohmann::json j;
      j["effector"] = t.effector;
      j["target"] = t.position;
      j["reached"] = {r.reached[3 * e], r.reached[3 * e + 1], r.reached[3 * e + 2]};
      j["error_m"] = error_of(r.reached, e, t);
      if (!equilibrium.empty()) {
        j["equilibrium"] = {equilibrium[3 * e], equilibrium[3 * e + 1], equilibrium[3 * e + 2]};
        j["equilibrium_error_m"] = error_of(equilibrium, e, t);
      }
      j["step_ms"] = r.total_ms;
      j["actuation"] = r.actuation;
      j["saturated"] = r.saturated;
      j["limit_point"] = limit_point;
      j["step"] = recorder.written() - 1;
      out["targets"].push_back(j);
      if (config.control->targets_from_stdin && rank == 0)
        std::cout << nlohmann::json({{"answer", j}}).dump() << std::endl;
    }
  }
  auto timing = [](const std::vector<double>& v) {
    return nlohmann::json{{"median", percentile(v, 0.5)}, {"p95", percentile(v, 0.95)}};
  };
  out["step_time_ms"] = timing(total);
  for (const auto& [name, v] : parts)
    out["step_time_ms"]["split_median"][name] = percentile(v, 0.5);
  out["step_time_ms"]["steps"] = total.size();
  out["qp"] = {{"kkt_residual_max", kkt_max}, {"unsolved", unsolved}};
  return out;
}

}  // namespace hs
