#include "solvers/output/result_recorder.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "io/write_together.hpp"

namespace hs {

std::unique_ptr<OutputFolder> open_output_folder(const std::string& folder, MPI_Comm comm) {
  // Every rank reads the deck itself, and the deck's check of output.folder looks at this
  // folder's staging folder: until rank 0 has written its marker there, a rank still reading
  // would find it foreign and stop alone, leaving the others waiting. So no rank makes the
  // staging folder before every rank has come this far.
  MPI_Barrier(comm);
  std::unique_ptr<OutputFolder> opened;
  on_rank_zero(comm, [&] {
    try {
      opened = std::make_unique<OutputFolder>(folder);
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw std::runtime_error("output folder '" + folder + "': " + e.what());
    }
  });
  return opened;
}

std::vector<double> ResultRecorder::owned_values(Vec v) const {
  const PetscScalar* a;
  HS_PETSC(VecGetArrayRead(v, &a));
  std::vector<double> values(a, a + 3 * problem_.distribution().num_owned());
  HS_PETSC(VecRestoreArrayRead(v, &a));
  return values;
}

OutputLayout output_layout(const Distribution& dist, MPI_Comm comm) {
  OutputLayout l;
  l.order = dist.order;
  l.nodes = dist.num_global();
  l.tets = dist.num_global_tets;
  l.first_node = dist.owned_offsets[dist.rank];
  const int64_t mine = static_cast<int64_t>(dist.local_tets.size());
  MPI_Exscan(&mine, &l.first_tet, 1, MPI_INT64_T, MPI_SUM, comm);
  if (dist.rank == 0) l.first_tet = 0;
  l.x.assign(dist.x.begin(), dist.x.begin() + 3 * dist.num_owned());
  l.node_ids.assign(dist.old_of_local.begin(), dist.old_of_local.begin() + dist.num_owned());
  l.tet_ids = dist.local_tets;
  l.topology.reserve(dist.tet_nodes.size());
  for (int32_t n : dist.tet_nodes) l.topology.push_back(dist.local_nodes[n]);
  l.volume_group = dist.tet_volume;
  l.volume_names = dist.groups.volumes;
  // Every rank lists the whole mesh's groups (in the map's order), so the writes match.
  const auto& volumes = dist.groups.volumes;
  for (const auto& entry : dist.groups.group_nodes) {
    const std::string& name = entry.first;
    if (std::find(volumes.begin(), volumes.end(), name) != volumes.end()) continue;
    OutputLayout::NodeGroup group{name, std::vector<int>(dist.num_owned(), 0)};
    auto it = dist.node_groups.find(name);
    if (it != dist.node_groups.end())
      for (int32_t n : it->second)
        if (n < dist.num_owned()) group.mask[n] = 1;  // ghosts are their owner's rows
    l.node_groups.push_back(std::move(group));
  }
  return l;
}

void add_reactions(Problem& problem, Vec u, double s, HistoryRow& row) {
  const auto& groups = problem.reaction_groups();
  if (groups.empty()) return;
  const auto forces = problem.reactions(u, s);
  for (size_t g = 0; g < groups.size(); ++g)
    for (int d = 0; d < 3; ++d)
      row.add("reaction_" + groups[g] + "_" + "xyz"[d] + "_N", forces[g][d]);
}

nlohmann::json reactions_json(Problem& problem, Vec u, double s) {
  nlohmann::json out = nlohmann::json::object();
  const auto& groups = problem.reaction_groups();
  if (groups.empty()) return out;
  const auto forces = problem.reactions(u, s);
  for (size_t g = 0; g < groups.size(); ++g)
    out[groups[g]] = {forces[g][0], forces[g][1], forces[g][2]};
  return out;
}

void add_contact(Problem& problem, Vec u, double s, HistoryRow& row) {
  if (problem.self_contact()) {
    const SelfContact::Totals t = problem.self_contact_totals(u);
    row.add("self_contact_pairs", static_cast<double>(t.pairs));
    row.add("self_contact_force_N", t.force);
    if (problem.self_contact()->has_friction()) row.add("self_contact_friction_N", t.friction);
  }
  if (!problem.contact()) return;
  const auto totals = problem.contact_totals(u, s);
  const auto& obstacles = problem.contact()->obstacles();
  for (size_t o = 0; o < obstacles.size(); ++o) {
    for (int d = 0; d < 3; ++d)
      row.add("contact_" + obstacles[o].name + "_" + "xyz"[d] + "_N", totals.force[o][d]);
    row.add("contact_" + obstacles[o].name + "_area_m2", totals.area[o]);
  }
}

nlohmann::json contact_json(Problem& problem, Vec u, double s) {
  nlohmann::json out = nlohmann::json::object();
  if (const SelfContact* self = problem.self_contact()) {
    const SelfContact::Totals t = problem.self_contact_totals(u);
    out["self"] = {{"pairs", t.pairs},
                   {"force_N", t.force},
                   {"min_gap_m", t.pairs > 0 ? nlohmann::json(t.min_gap) : nlohmann::json()},
                   {"nodes", self->num_nodes()}};
    if (self->has_friction()) out["self"]["friction_N"] = t.friction;
    out["distance_m"] = self->barrier().distance;
    out["stiffness_Pa_per_m"] = self->barrier().stiffness;
  }
  if (!problem.contact()) return out;
  const auto totals = problem.contact_totals(u, s);
  const auto& obstacles = problem.contact()->obstacles();
  out["obstacles"] = nlohmann::json::array();
  for (size_t o = 0; o < obstacles.size(); ++o)
    out["obstacles"].push_back({{"obstacle", obstacles[o].name},
                                {"force_N", totals.force[o]},
                                {"area_m2", totals.area[o]}});
  out["min_gap_m"] = totals.min_gap;
  if (problem.contact()->holds_forces()) {  // control.contact_forces: qp, no barrier
    out["law"] = "held forces";
    out["loaded_gap_m"] = totals.loaded_gap;
    return out;
  }
  out["distance_m"] = problem.contact()->barrier().distance;
  out["stiffness_Pa_per_m"] = problem.contact()->barrier().stiffness;
  out["nodes"] = problem.contact()->num_nodes();
  return out;
}

ResultRecorder::ResultRecorder(Problem& problem, const Config& config,
                               std::unique_ptr<OutputFolder> folder, MPI_Comm comm)
    : problem_(problem), comm_(comm), folder_(std::move(folder)) {
  MPI_Comm_rank(comm, &rank_);
  // Every rank writes into rank 0's staging folder.
  staging_ = rank_ == 0 ? folder_->staging() : std::string();
  broadcast_string(staging_, 0, comm);
  writer_ = std::make_unique<XdmfWriter>(comm, staging_, config.deck_name,
                                         output_layout(problem.distribution(), comm));
  load_ = VecHandle(problem.create_vector());
}

ResultRecorder::~ResultRecorder() = default;

void ResultRecorder::record(double time, Vec u, double s, const std::string& time_kind) {
  const double t0 = MPI_Wtime();
  StepFields f;
  f.time = time;
  f.displacement = owned_values(u);
  f.time_kind = time_kind.empty() ? sources_.time_column : time_kind;
  problem_.external_load(u, s, load_);
  f.nodal_load = owned_values(load_);
  // The parts of that load, as the residual last had them (the cavities' pressures on their
  // walls, the liquids' weights): nodal_load minus these is gravity, the deck's pressures and
  // the cables' forces.
  if (constraints_ && problem_.has_cavity_surfaces()) {
    problem_.cavity_pressure_load(u, load_);
    f.cavity_pressure_load = owned_values(load_);
    if (constraints_->fluid_weight_load(load_)) f.fluid_weight_load = owned_values(load_);
  }
  {
    Problem::ElementFieldValues v;
    problem_.element_fields(u, v);
    f.von_mises = std::move(v.von_mises);
    f.J = std::move(v.J);
    f.stress = std::move(v.stress);
    f.strain = std::move(v.strain);
    f.principal_stress = std::move(v.principal_stress);
    f.principal_strain = std::move(v.principal_strain);
  }
  f.pressure = problem_.nodal_pressure(u);
  if (problem_.contact()) {
    auto c = problem_.contact_node_values(u, s);
    f.node_fields.push_back({"contact_gap", 1, "m", std::move(c.gap)});
    f.node_fields.push_back({"contact_pressure", 1, "Pa", std::move(c.pressure)});
    if (problem_.contact()->has_friction())
      f.node_fields.push_back({"friction_traction", 3, "Pa", std::move(c.friction)});
  }
  if (problem_.self_contact()) {
    auto c = problem_.self_contact_node_values(u);
    f.node_fields.push_back({"self_contact_gap", 1, "m", std::move(c.gap)});
    f.node_fields.push_back({"self_contact_pressure", 1, "Pa", std::move(c.pressure)});
    if (!c.friction.empty())
      f.node_fields.push_back({"self_contact_friction", 3, "Pa", std::move(c.friction)});
  }
  f.rank.assign(f.J.size(), rank_);
  HistoryRow row;
  row.add_count("step", written_);
  row.add(sources_.time_column, time);
  const int newton = sources_.newton_iterations ? sources_.newton_iterations() : 0;
  if (sources_.newton_iterations) row.add_count("newton_iterations", newton - newton_at_last_row_);
  for (const auto& columns : sources_.columns) columns(u, row);
  add_reactions(problem_, u, s, row);
  add_contact(problem_, u, s, row);
  // Refuses a non-finite value on every rank, before writing; a file that cannot be written
  // stops every rank with SolveError.
  writer_->write_step(f);
  ++written_;
  newton_at_last_row_ = newton;
  // Only rank 0 writes the file; every rank keeps the rows for the .h5's collective write.
  write_together(comm_, true, [&] {
    history_.append(row, rank_ == 0 ? staging_ + "/history.csv" : std::string());
  });
  seconds_ += MPI_Wtime() - t0;
}

void ResultRecorder::close_files() {
  const double t0 = MPI_Wtime();
  writer_->close();
  history_.write_h5(staging_ + "/" + writer_->h5_file(), comm_);
  seconds_ += MPI_Wtime() - t0;
}

std::string ResultRecorder::finish(nlohmann::json& summary) {
  std::string folder;
  try {
    close_files();
    summary["status"] = "ok";
    write_together(comm_, rank_ == 0, [&] {
      write_json(folder_->staging() + "/summary.json", summary);
      folder_->commit();
      folder = folder_->final();
    });
  } catch (SolveError& e) {
    // Every step converged, but the results could not be completed (a full disk): they are
    // kept as a failed run's, and the run fails.
    summary.erase("status");
    e.kept_in = keep_failed(summary, e.what());
    e.kept_steps = e.kept_in.empty() ? 0 : written_;
    throw;
  }
  return folder;
}

std::string ResultRecorder::keep_failed(nlohmann::json summary, const std::string& reason) {
  // Nothing to keep without an output step or a checkpoint to restart from.
  int checkpoint = rank_ == 0 && std::filesystem::exists(staging_ + "/checkpoint.h5");
  MPI_Bcast(&checkpoint, 1, MPI_INT, 0, comm_);
  if (written_ == 0 && !checkpoint) return {};
  writer_->close();
  // Best effort, each part on its own: on a full disk what needs no room (the rename) must
  // still happen. The .xmf already names every step written.
  try {
    if (written_ > 0) history_.write_h5(staging_ + "/" + writer_->h5_file(), comm_);
  } catch (const SolveError&) {
    // The .h5 goes without /history: history.csv has the rows.
  }
  std::string kept;
  if (rank_ == 0) {
    summary["status"] = "failed";
    summary["reason"] = reason;
    summary["last_converged"] = history_.last_row();
    summary["output"]["folder"] = folder_->final() + ".failed";
    summary["output"]["xdmf"] = folder_->final() + ".failed/" + writer_->xdmf_file();
    try {
      write_json(folder_->staging() + "/summary.json", summary);
    } catch (const std::exception& e) {
      std::cerr << "hydrosoft: warning: the kept steps have no summary.json: " << e.what()
                << std::endl;
    }
    try {
      kept = folder_->keep_failed();
    } catch (const std::exception& e) {
      std::cerr << "hydrosoft: warning: the converged steps could not be kept: " << e.what()
                << std::endl;
    }
  }
  broadcast_string(kept, 0, comm_);
  return kept;
}

std::string ResultRecorder::xdmf_path() const {
  return rank_ == 0 ? folder_->final() + "/" + writer_->xdmf_file() : std::string();
}

}  // namespace hs
