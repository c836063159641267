#include "solvers/checkpoint.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <unordered_map>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "deck/config_fingerprint.hpp"
#include "solvers/stepping/stepping_kind.hpp"

namespace hs {
namespace {

// An order-free fingerprint of the mesh's nodes: sum over nodes of (x + 2y + 3z) weighted by
// its id modulo 7, and the sum of the magnitudes (the scale of its rounding). Collective.
std::array<double, 2> coordinate_checksum(const Distribution& dist, MPI_Comm comm) {
  std::array<double, 2> sum{0, 0};
  for (int64_t i = 0; i < dist.num_owned(); ++i) {
    const double* x = &dist.x[3 * i];
    const double term = (x[0] + 2 * x[1] + 3 * x[2]) * (1 + dist.old_of_local[i] % 7);
    sum[0] += term;
    sum[1] += std::abs(term);
  }
  MPI_Allreduce(MPI_IN_PLACE, sum.data(), 2, MPI_DOUBLE, MPI_SUM, comm);
  return sum;
}

std::vector<double> owned_values(const Problem& problem, Vec v) {
  const PetscScalar* a;
  HS_PETSC(VecGetArrayRead(v, &a));
  std::vector<double> values(a, a + 3 * problem.distribution().num_owned());
  HS_PETSC(VecRestoreArrayRead(v, &a));
  return values;
}

double wall_minutes(MPI_Comm comm) {
  double t = MPI_Wtime() / 60;
  MPI_Bcast(&t, 1, MPI_DOUBLE, 0, comm);  // rank 0's clock decides for every rank
  return t;
}

}  // namespace

std::string stepping_kind(const Config& config) {
  return stepping_kind_name(stepping_kind_of(config));
}

void check_checkpoint_use(const Config& config, bool restart) {
  if (!config.control || !config.control->targets_from_stdin) return;
  const std::string why =
      " (an interactive session's targets come from its client, which a restart cannot take "
      "back to the line where it stopped; start the session again from the deck)";
  if (config.output.checkpoint)
    throw InputError(config.deck_path + ": output.checkpoint: not supported with --targets -" +
                     why);
  if (restart) throw InputError("--restart: not supported with --targets -" + why);
}

Checkpointer::Checkpointer(const Config& config, const Problem& problem, const SteppingStats& stats,
                           std::string folder, MPI_Comm comm)
    : config_(config),
      problem_(problem),
      stats_(stats),
      path_(std::move(folder) + "/checkpoint.h5"),
      comm_(comm),
      active_(config.output.checkpoint.has_value()) {
  if (active_) last_time_ = wall_minutes(comm);
}

bool Checkpointer::due(bool signal) {
  if (!active_) return false;
  ++steps_since_;
  const CheckpointConfig& c = *config_.output.checkpoint;
  if (signal || (c.every > 0 && steps_since_ >= c.every)) return true;
  return c.minutes > 0 && wall_minutes(comm_) - last_time_ >= c.minutes;
}

void Checkpointer::start_count() {
  steps_since_ = 0;
  if (active_) last_time_ = wall_minutes(comm_);
}

void Checkpointer::write(nlohmann::json position, const NamedVecs& fields,
                         const NamedValues& series, const NamedValues& element_fields) {
  const Distribution& dist = problem_.distribution();
  int size = 1;
  MPI_Comm_size(comm_, &size);
  nlohmann::json state;
  state["kind"] = stepping_kind(config_);
  state["fingerprint"] = config_fingerprint(config_);
  state["deck"] = config_.deck_path;
  state["nodes"] = dist.num_global();
  state["elements"] = dist.num_global_tets;
  state["order"] = dist.order;
  state["ranks"] = size;
  const auto checksum = coordinate_checksum(dist, comm_);
  state["coordinate_checksum"] = {checksum[0], checksum[1]};
  state["stats"] = {{"steps", stats_.steps},
                    {"cutbacks", stats_.cutbacks},
                    {"newton_iterations", stats_.newton_iterations},
                    {"linear_iterations", stats_.linear_iterations},
                    {"max_stored_energy", stats_.max_stored_energy}};
  state["position"] = std::move(position);
  CheckpointRows rows;
  rows.nodes = dist.num_global();
  rows.first = dist.owned_offsets[dist.rank];
  rows.node_ids.assign(dist.old_of_local.begin(), dist.old_of_local.begin() + dist.num_owned());
  NamedValues values;
  for (const auto& [name, v] : fields) values.emplace_back(name, owned_values(problem_, v));
  if (!element_fields.empty()) {  // each tetrahedron is on one rank
    rows.elements = dist.num_global_tets;
    const int64_t count = static_cast<int64_t>(dist.local_tets.size());
    MPI_Exscan(&count, &rows.first_element, 1, MPI_INT64_T, MPI_SUM, comm_);
    if (dist.rank == 0) rows.first_element = 0;
    rows.element_ids = dist.local_tets;
  }
  write_checkpoint(path_, comm_, state, rows, values, series, element_fields);
  ++written_;
  steps_since_ = 0;
  if (config_.output.checkpoint->minutes > 0) last_time_ = wall_minutes(comm_);
}

Restart::Restart(const std::string& folder, const Config& config, MPI_Comm comm)
    : folder_(folder), comm_(comm) {
  std::error_code ignored;  // a path that cannot be examined is refused as missing, below
  const std::string path =
      std::filesystem::is_directory(folder, ignored) ? folder + "/checkpoint.h5" : folder;
  std::string error;
  try {
    file_ = std::make_unique<CheckpointFile>(path);
    check_checkpoint_state(file_->state(), config, path);
    if (stepping_kind(config) == "dynamic" || stepping_kind(config) == "dynamic_states") {
      // The total energy after every step so far, and the initial one.
      const size_t step = file_->state().at("position").at("step").get<size_t>();
      const std::vector<double> energy = file_->series("energy");
      if (energy.size() != step + 1 ||
          !std::all_of(energy.begin(), energy.end(), [](double e) { return std::isfinite(e); }))
        error = "--restart: " + path + ": /series/energy: must hold " + std::to_string(step + 1) +
                " finite values (the initial energy and one per step done), has " +
                std::to_string(energy.size()) + " values";
    }
  } catch (const InputError& e) {
    error = e.what();
  } catch (const std::exception& e) {
    error = "--restart: " + path + ": " + e.what();
  }
  throw_together<InputError>(error, comm);
}

void Restart::check_mesh(const Problem& problem) const {
  const Distribution& dist = problem.distribution();
  const nlohmann::json& s = file_->state();
  const auto checksum = coordinate_checksum(dist, comm_);
  std::string reason;
  if (s.value("nodes", int64_t{-1}) != dist.num_global() || file_->nodes() != dist.num_global() ||
      s.value("elements", int64_t{-1}) != dist.num_global_tets ||
      s.value("order", 0) != dist.order) {
    reason = "written on a mesh of " + std::to_string(s.value("nodes", int64_t{-1})) +
             " nodes and " + std::to_string(s.value("elements", int64_t{-1})) + " P" +
             std::to_string(s.value("order", 0)) + " tetrahedra; this deck's has " +
             std::to_string(dist.num_global()) + " nodes and " +
             std::to_string(dist.num_global_tets) + " P" + std::to_string(dist.order);
  } else {
    const double written = s.at("coordinate_checksum").at(0).get<double>();
    if (std::abs(written - checksum[0]) > 1e-10 * checksum[1] + 1e-300)
      reason = "written on a mesh of the same size but other node coordinates";
  }
  if (!reason.empty()) throw InputError("--restart: " + file_->path() + ": " + reason);
}

namespace {

// A file's rows placed by id: each rank reads a block of the n rows (`ids` and `values`, up to
// 3 values a row, read a block [begin, end)) and sends each row to the rank that keeps the
// ids of its block (a directory by id); each rank then asks the directory for the ids it
// wants and gets their rows back, `width` values each, in the order of `wanted`. `found`
// says which the file has. Collective; InputError on every rank, naming the dataset, for an
// id out of range or a value that is not finite (a damaged or edited file).
struct IdRow {
  int64_t id;
  double value[3];
};

std::vector<double> rows_by_id(int64_t n, int width, const std::string& noun,
                               const std::string& dataset,
                               const std::function<std::vector<int64_t>(int64_t, int64_t)>& ids,
                               const std::function<std::vector<double>(int64_t, int64_t)>& values,
                               const std::vector<int64_t>& wanted, const std::string& path,
                               std::vector<char>& found, MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  std::string error;
  const int64_t begin = block_begin(n, rank, size), end = block_begin(n, rank + 1, size);
  std::vector<std::vector<IdRow>> to_directory(size);
  try {
    const auto id = ids(begin, end);
    const auto value = values(begin, end);
    for (size_t i = 0; i < id.size(); ++i) {
      if (id[i] < 0 || id[i] >= n) {
        error =
            "--restart: " + path + ": " + noun + " id " + std::to_string(id[i]) + " out of range";
        break;
      }
      IdRow row{id[i], {0, 0, 0}};
      for (int c = 0; c < width; ++c) row.value[c] = value[width * i + c];
      if (!std::isfinite(row.value[0] + row.value[1] + row.value[2])) {
        error = "--restart: " + path + ": " + dataset + ": " + noun + " " + std::to_string(id[i]) +
                " holds a value that is not a finite number";
        break;
      }
      to_directory[block_owner(n, id[i], size)].push_back(row);
    }
  } catch (const InputError& e) {
    error = e.what();
  }
  throw_together<InputError>(error, comm);
  const std::vector<IdRow> kept = all_to_all(to_directory, comm);
  std::vector<IdRow> directory(end - begin, IdRow{-1, {0, 0, 0}});
  for (const IdRow& row : kept) directory[row.id - begin] = row;
  std::vector<std::vector<int64_t>> asks(size);
  for (const int64_t id : wanted) asks[block_owner(n, id, size)].push_back(id);
  std::vector<int64_t> from;
  const std::vector<int64_t> asked = all_to_all(asks, comm, &from);
  std::vector<std::vector<IdRow>> answers(size);
  size_t next = 0;
  for (int r = 0; r < size; ++r)
    for (int64_t k = 0; k < from[r]; ++k, ++next)
      answers[r].push_back(directory[asked[next] - begin]);
  const std::vector<IdRow> answered = all_to_all(answers, comm);
  std::unordered_map<int64_t, size_t> index_of;
  for (size_t i = 0; i < wanted.size(); ++i) index_of[wanted[i]] = i;
  std::vector<double> out(width * wanted.size(), 0.0);
  found.assign(wanted.size(), 0);
  for (const IdRow& row : answered) {
    const auto it = index_of.find(row.id);
    if (it == index_of.end()) continue;  // a row the file lacks (id -1)
    for (int c = 0; c < width; ++c) out[width * it->second + c] = row.value[c];
    found[it->second] = 1;
  }
  return out;
}

}  // namespace

void Restart::read(const std::string& name, const Problem& problem, Vec v) const {
  const Distribution& dist = problem.distribution();
  const std::vector<int64_t> wanted(dist.old_of_local.begin(),
                                    dist.old_of_local.begin() + dist.num_owned());
  std::vector<char> found;
  const std::vector<double> rows = rows_by_id(
      file_->nodes(), 3, "node", "/fields/" + name,
      [&](int64_t b, int64_t e) { return file_->node_ids(b, e); },
      [&](int64_t b, int64_t e) { return file_->field(name, b, e); }, wanted, file_->path(), found,
      comm_);
  PetscScalar* a;
  HS_PETSC(VecGetArray(v, &a));
  for (size_t i = 0; i < 3 * wanted.size(); ++i) a[i] = rows[i];
  HS_PETSC(VecRestoreArray(v, &a));
  HS_PETSC(VecGhostUpdateBegin(v, INSERT_VALUES, SCATTER_FORWARD));
  HS_PETSC(VecGhostUpdateEnd(v, INSERT_VALUES, SCATTER_FORWARD));
  throw_together<InputError>(std::count(found.begin(), found.end(), 1) == dist.num_owned()
                                 ? std::string()
                                 : "--restart: " + file_->path() + ": /fields/" + name +
                                       " lacks some of this mesh's nodes",
                             comm_);
}

std::vector<double> Restart::read_elements(const std::string& name, const Problem& problem) const {
  const Distribution& dist = problem.distribution();
  int has = file_->has_element_field(name) && file_->elements() == dist.num_global_tets;
  MPI_Allreduce(MPI_IN_PLACE, &has, 1, MPI_INT, MPI_MIN, comm_);
  if (!has) return {};
  std::vector<char> found;
  const std::vector<double> values = rows_by_id(
      file_->elements(), 1, "element", "/element_fields/" + name,
      [&](int64_t b, int64_t e) { return file_->element_ids(b, e); },
      [&](int64_t b, int64_t e) { return file_->element_field(name, b, e); }, dist.local_tets,
      file_->path(), found, comm_);
  throw_together<InputError>(std::count(found.begin(), found.end(), 0) == 0
                                 ? std::string()
                                 : "--restart: " + file_->path() + ": /element_fields/" + name +
                                       " lacks some of this mesh's elements",
                             comm_);
  return values;
}

void Restart::restore(SteppingStats& stats) const {
  const nlohmann::json& s = file_->state().at("stats");
  stats.steps = s.at("steps");
  stats.cutbacks = s.at("cutbacks");
  stats.newton_iterations = s.at("newton_iterations");
  stats.linear_iterations = s.at("linear_iterations");
  stats.max_stored_energy = s.at("max_stored_energy");
}

nlohmann::json Restart::summary() const {
  nlohmann::json j;
  j["folder"] = folder_;
  j["file"] = file_->path();
  j["ranks"] = file_->state().value("ranks", 0);
  j["position"] = position();
  // The results so far (a control loop's, the states', the verification history), the
  // controller's and the constraints' states are the run's summary already or its internals,
  // not where it went on from.
  for (const char* bulky : {"loop", "controller", "states", "verification", "constraints"})
    j["position"].erase(bulky);
  return j;
}

nlohmann::json constraint_states(const ConstraintSet& constraints) {
  nlohmann::json list = nlohmann::json::array();
  for (int k = 0; k < constraints.size(); ++k) {
    const Constraint& c = constraints[k];
    const Constraint::State s = c.snapshot();
    list.push_back({{"name", c.name()},
                    {"lambda", s.multiplier},
                    {"target", s.target},
                    {"control", static_cast<int>(s.control)},
                    {"measure", s.measure},
                    {"rest_measure", s.rest_measure}});
  }
  return list;
}

void restore_constraint_states(ConstraintSet& constraints, const nlohmann::json& states) {
  if (static_cast<int>(states.size()) != constraints.size())
    throw InputError("--restart: the checkpoint holds " + std::to_string(states.size()) +
                     " constraints, this deck has " + std::to_string(constraints.size()));
  for (int k = 0; k < constraints.size(); ++k) {
    Constraint& c = constraints[k];
    const nlohmann::json& s = states[k];
    if (s.at("name") != c.name())
      throw InputError("--restart: the checkpoint's constraint " + std::to_string(k) + " is '" +
                       s.at("name").get<std::string>() + "', this deck's '" + c.name() + "'");
    Constraint::State state;
    state.multiplier = s.at("lambda");
    state.target = s.at("target");
    state.control = static_cast<Constraint::Control>(s.at("control").get<int>());
    state.measure = s.at("measure");
    state.rest_measure = s.at("rest_measure");
    c.restore(state);
  }
}

}  // namespace hs
