#include "solvers/output/result_recorder.hpp"

#include <cmath>
#include <stdexcept>

#include "common/error.hpp"
#include "solvers/output/gather.hpp"

namespace hs {
namespace {

// Rank 0's outcome, shared: 0 done, 1 an InputError, 2 any other error; then its message.
void share_outcome(int& outcome, std::string& message, MPI_Comm comm) {
  MPI_Bcast(&outcome, 1, MPI_INT, 0, comm);
  int n = static_cast<int>(message.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, comm);
  message.resize(n);
  MPI_Bcast(message.data(), n, MPI_CHAR, 0, comm);
}

}  // namespace

std::unique_ptr<OutputFolder> open_output_folder(const std::string& folder, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::unique_ptr<OutputFolder> opened;
  int outcome = 0;
  std::string message;
  if (rank == 0) {
    try {
      opened = std::make_unique<OutputFolder>(folder);
    } catch (const InputError& e) {
      outcome = 1;
      message = e.what();
    } catch (const std::exception& e) {
      outcome = 2;
      message = "output folder '" + folder + "': " + e.what();
    }
  }
  share_outcome(outcome, message, comm);
  if (outcome == 1) throw InputError(message);
  if (outcome == 2) throw std::runtime_error(message);
  return opened;
}

ResultRecorder::ResultRecorder(Problem& problem, const Config& config,
                               std::unique_ptr<OutputFolder> folder, MPI_Comm comm)
    : problem_(problem), folder_(std::move(folder)) {
  MPI_Comm_rank(comm, &rank_);
  if (rank_ == 0) {
    writer_ = std::make_unique<XdmfWriter>(folder_->staging(), config.deck_name, problem.mesh());
  }
  load_ = problem.create_vector();
}

ResultRecorder::~ResultRecorder() { VecDestroy(&load_); }

void ResultRecorder::record(double time, Vec u, double s) {
  StepFields f;
  f.time = time;
  f.displacement = gather_nodal(problem_, u);
  problem_.external_load(u, s, load_);
  f.nodal_load = gather_nodal(problem_, load_);
  std::vector<double> vm, J;
  problem_.element_fields(u, vm, J);
  f.von_mises = gather_elemental(problem_, vm);
  f.J = gather_elemental(problem_, J);
  std::vector<double> rank(vm.size(), problem_.distribution().rank);
  const auto ranks = gather_elemental(problem_, rank);
  // Decided together, so that every rank stops on a non-finite result, not rank 0 alone.
  int finite = 1;
  for (const auto* field : {&f.displacement, &f.nodal_load, &f.von_mises, &f.J})
    for (double x : *field) finite &= std::isfinite(x);
  MPI_Bcast(&finite, 1, MPI_INT, 0, problem_.comm());
  if (!finite)
    throw SolveError("output at time/load " + std::to_string(time) +
                     ": a computed field is not finite; nothing was written");
  if (rank_ != 0) return;
  f.rank.assign(ranks.begin(), ranks.end());
  writer_->write_step(f);
  ++written_;
}

std::string ResultRecorder::finish(const nlohmann::json& summary) {
  if (rank_ != 0) return {};
  writer_->close();
  write_json(folder_->staging() + "/summary.json", summary);
  folder_->commit();
  return folder_->final();
}

std::string ResultRecorder::xdmf_path() const {
  return rank_ == 0 ? folder_->final() + "/" + writer_->xdmf_file() : std::string();
}

}  // namespace hs
