#include "solvers/run_output.hpp"

#include <sys/resource.h>

#include <algorithm>

namespace hs {

HistorySources history_sources(const Config& config, bool staged, ConstraintSet* constraints,
                               const SteppingStats& stats) {
  HistorySources sources;
  sources.time_column = staged                                  ? "state"
                        : config.time.type == TimeType::dynamic ? "time_s"
                                                                : "load_factor";
  sources.newton_iterations = [&stats] { return stats.newton_iterations; };
  if (constraints)
    sources.columns.push_back(
        [constraints](Vec, HistoryRow& row) { constraints->add_history(row); });
  return sources;
}

void add_timings(nlohmann::json& summary, const Problem& problem, const Distribution& dist,
                 const MeshLoadTimes& mesh_times, const ResultRecorder& recorder, MPI_Comm comm) {
  const auto& t = problem.timers();
  double assembly = t.residual_s + t.jacobian_s;
  MPI_Allreduce(MPI_IN_PLACE, &assembly, 1, MPI_DOUBLE, MPI_MAX, comm);
  summary["time_s"]["setup_mesh"] = mesh_times.read_s;
  summary["time_s"]["setup_partition"] = mesh_times.partition_s;
  summary["time_s"]["setup_distribute"] = mesh_times.distribute_s;
  double output_s = recorder.seconds();
  MPI_Allreduce(MPI_IN_PLACE, &output_s, 1, MPI_DOUBLE, MPI_MAX, comm);
  summary["time_s"]["output"] = output_s;
  // The largest rank's share of the mesh: its tetrahedra and its local (owned + ghost) nodes.
  int64_t largest[2] = {static_cast<int64_t>(dist.local_tets.size()), dist.num_local()};
  MPI_Allreduce(MPI_IN_PLACE, largest, 2, MPI_INT64_T, MPI_MAX, comm);
  summary["mesh"]["largest_rank_tets"] = largest[0];
  summary["mesh"]["largest_rank_nodes"] = largest[1];
  summary["time_s"]["assembly"] = assembly;
  if (problem.has_contact()) {
    double contact = t.contact_s;
    MPI_Allreduce(MPI_IN_PLACE, &contact, 1, MPI_DOUBLE, MPI_MAX, comm);
    summary["time_s"]["contact"] = contact;
  }
  // Peak resident memory: the largest rank's, and the sum over ranks.
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  double rss_mb = usage.ru_maxrss / 1024.0, rss_max = 0, rss_sum = 0;
  MPI_Allreduce(&rss_mb, &rss_max, 1, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(&rss_mb, &rss_sum, 1, MPI_DOUBLE, MPI_SUM, comm);
  summary["memory_mb"]["peak_rank_max"] = rss_max;
  summary["memory_mb"]["peak_total"] = rss_sum;
  // Tangent assemblies (element residual + tangent + insertion) per second, all ranks together.
  double jacobian_s = t.jacobian_s;
  MPI_Allreduce(MPI_IN_PLACE, &jacobian_s, 1, MPI_DOUBLE, MPI_MAX, comm);
  summary["assembly"]["jacobian_calls"] = t.jacobian_calls;
  summary["assembly"]["elements_per_second"] =
      t.jacobian_calls > 0 ? dist.num_global_tets * t.jacobian_calls / std::max(jacobian_s, 1e-12)
                           : 0.0;
}

void keep_converged_steps(SolveError& error, ResultRecorder& recorder, nlohmann::json summary,
                          MPI_Comm) {
  error.kept_in = recorder.keep_failed(std::move(summary), error.what());
  error.kept_steps = error.kept_in.empty() ? 0 : recorder.written();
}

}  // namespace hs
