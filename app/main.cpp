// hydrosoft: nonlinear FEM of soft robots driven by hydraulic and pneumatic cavities.
//
//   mpirun -np N build/bin/hydrosoft input/<deck>.yaml [--set key=value ...] [-petsc_option ...]
//
// The deck is validated before any work and printed resolved; --set overrides a deck key
// (e.g. --set mesh.order=2); every PETSc option can be given on the command line and wins
// over the deck's solver.petsc_options, unprefixed for every solver object or with one
// object's prefix for it alone (solvers/solver_options.hpp).
#include <fcntl.h>
#include <petscsys.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "common/exchange.hpp"
#include "common/interrupt.hpp"
#include "deck/boundary_conflicts.hpp"
#include "deck/deck.hpp"
#include "deck/exact_section.hpp"
#include "io/hdf5_file.hpp"
#include "mesh/gmsh_io.hpp"
#include "mesh/mesh_h5.hpp"
#include "mesh/mesh_statistics.hpp"
#include "mesh/rigid_motions.hpp"
#include "run_report.hpp"
#include "solvers/blas_threads.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/simulation.hpp"
#include "solvers/solver_options.hpp"
#include "solvers/verification/reference_check.hpp"
#include "version.hpp"

namespace {

const char* usage =
    "usage: hydrosoft DECK.yaml [--set key=value ...] [--targets -] [--restart FOLDER]\n"
    "                 [PETSc options]\n"
    "       hydrosoft --check DECK.yaml [--set key=value ...]\n"
    "       hydrosoft mesh DECK.yaml OUT.h5 [--set key=value ...]\n"
    "       hydrosoft reduce DECK.yaml -o MODEL.h5 [--samples N] [--design grid|halton]\n"
    "                 [--pod-tolerance E] [--ecsw-tolerance T] [--set key=value ...]\n"
    "       hydrosoft --version | --help\n"
    "  --check           validate the deck, load or mesh its mesh, check its groups, print the\n"
    "                    resolved configuration and the mesh's statistics; solve nothing\n"
    "  mesh              mesh (or read) the deck's mesh once and write it to OUT.h5, which a\n"
    "                    deck names as mesh.file and every rank of a run reads its part of\n"
    "  reduce            train a reduced-order model of a control deck: the full model at N\n"
    "                    samples of each actuator's range (--samples, default 17; with\n"
    "                    --design halton, for three actuators or more, N in all: the box's\n"
    "                    corners and a Halton sequence), POD (the\n"
    "                    discarded energy, default 1e-10) and ECSW (the relative force error\n"
    "                    on the training samples, default 1e-6), checked on the held-back\n"
    "                    samples; a run then answers with it\n"
    "                    by --set control.reduced_model=MODEL.h5 (docs/reduced_models.md)\n"
    "  -q, --quiet       no progress line per step (the deck's output.progress: false)\n"
    "  -v, --verbose     the solvers' monitors: -snes_monitor -ksp_converged_reason and the\n"
    "                    cavities' Newton (-hs_bordered_monitor)\n"
    "  --set key=value   override a deck key, e.g. --set mesh.order=2 --set mesh.parameters.h=0.1\n"
    "  --targets -       read control targets from standard input, one per line: 'x y z' or\n"
    "                    'effector x y z'; each line gets one JSON line on standard output,\n"
    "                    its answer or why it was refused; the rest goes to standard error\n"
    "  --restart FOLDER  continue from FOLDER/checkpoint.h5 (the deck's output.checkpoint wrote\n"
    "                    it; FOLDER a finished, .failed or .partial output folder) on any number\n"
    "                    of ranks; the deck must be the one that wrote it, output keys aside\n"
    "  PETSc options     e.g. -snes_monitor -ksp_type cg -pc_type gamg (they win over the deck);\n"
    "                    one solver object's alone with its prefix: -hs_newton_, -hs_bordered_,\n"
    "                    -hs_control_ (e.g. -hs_control_ksp_type gmres; docs/decks.md)\n";

// In the interactive mode standard output carries the JSON lines alone, so that a client can
// read it line by line: its descriptor is kept for them (returned), and descriptor 1 becomes
// standard error, so that everything else the process prints (this program's messages,
// PETSc's monitors, a library's notes) goes there. -1 if the descriptors cannot be set.
int keep_stdout_for_answers() {
  std::fflush(stdout);
  const int answers = fcntl(STDOUT_FILENO, F_DUPFD_CLOEXEC, 3);
  if (answers < 0) return -1;
  if (dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
    close(answers);
    return -1;
  }
  return answers;
}

// One answer line, written whole at once: the client waits for it before its next target.
// False when it cannot be written: the client closed its end (EPIPE; SIGPIPE is ignored) or
// the descriptor failed otherwise. The session then ends and keeps its results.
bool write_answer_line(int fd, const std::string& line) {
  const std::string text = line + "\n";
  for (size_t done = 0; done < text.size();) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {  // a client's non-blocking pipe
      pollfd ready{fd, POLLOUT, 0};
      poll(&ready, 1, -1);
      continue;
    }
    if (n < 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

int fail(int code, const std::string& message) {
  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  if (rank == 0 || code == 4) std::cerr << "hydrosoft: error: " << message << std::endl;
  if (size > 1 && code == 4) MPI_Abort(PETSC_COMM_WORLD, code);  // a rank-local failure
  PetscFinalize();
  return code;
}

// A run that failed: its deck and why, as every error names its file, then where the steps
// it kept are. An interrupted run says so in one line and exits with 128 + the signal, as a process
// killed by it would (a batch system reads it so), but with its converged steps kept.
int stopped(const std::string& deck, const hs::SolveError& e) {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  const auto* interrupted = dynamic_cast<const hs::Interrupted*>(&e);
  std::string kept = "no step had converged: nothing was kept";
  if (!e.kept_in.empty()) {
    // A full disk may have left the kept folder without its summary, and a run stopped before
    // its first output step keeps only its checkpoint.
    const bool summary = std::filesystem::exists(e.kept_in + "/summary.json");
    kept = (e.kept_steps > 0
                ? "the " + std::to_string(e.kept_steps) + " converged output steps are in "
                : std::string("a checkpoint to restart from is in ")) +
           e.kept_in + "/" +
           (summary ? " (summary.json: \"status\": \"failed\")" : " (without a summary.json)");
  }
  if (!interrupted) return fail(3, deck + ": " + e.what() + "\n  " + kept);
  if (rank == 0) std::cerr << "hydrosoft: " << e.what() << "; " << kept << std::endl;
  PetscFinalize();
  return 128 + interrupted->signal;
}

// PETSc options of the command line that no object used: mistyped, or for a solver this scene
// does not run (scenes with cavities, cables, states or control run hydrosoft's own Newton).
void report_unused(const std::vector<std::string>& names) {
  for (const auto& name : names) {
    PetscBool used = PETSC_TRUE;
    PetscOptionsUsed(nullptr, name.c_str() + 1, &used);  // the database keeps names without "-"
    if (!used)
      std::cerr << "hydrosoft: warning: PETSc option " << name << " was not used"
                << (name.rfind("-snes", 0) == 0
                        ? " (mistyped, or a scene with cavities, cables, states or control: its "
                          "Newton is hydrosoft's bordered Newton, not SNES)"
                        : " (mistyped, or for a solver this run does not use)")
                << std::endl;
  }
}

// What the deck asks that runs but costs accuracy: a locking element (one line per material),
// or a real-time mode measured not to hold on a nearly incompressible body (docs/stiff_cases.md,
// "The shipped silicone decks at silicone's nu").
void print_deck_warnings(const hs::Config& config) {
  bool nodal_pressure = false;
  for (size_t i = 0; i < config.materials.size(); ++i) {
    nodal_pressure |= config.materials[i].element == hs::ElementFormulation::nodal_pressure;
    if (!config.materials[i].formulation_warning.empty())
      std::cerr << "hydrosoft: warning: materials[" << i << "] (group " << config.materials[i].group
                << "): " << config.materials[i].formulation_warning << std::endl;
  }
  const auto& control = config.control;
  if (nodal_pressure && control && control->free_solve == hs::FreeSolve::one_step &&
      (control->refactor_every > 1 || control->factor_threads > 0))
    std::cerr << "hydrosoft: warning: control."
              << (control->refactor_every > 1 ? "refactor_every > 1" : "factor_threads > 0")
              << " on a nodal-pressure body: its stale or background factorizations did not "
                 "track targets at nu 0.4995 (errors of 1 to 3 mm on the hydraulic finger; "
                 "docs/stiff_cases.md); refactor_every: 1 without factor_threads did"
              << std::endl;
}

// --check: the deck validated and printed resolved, its mesh loaded (or meshed) and its groups
// checked, the mesh's statistics printed; nothing solved, nothing written.
void check_deck(const hs::Config& config) {
  hs::check_solver_options(config.solver, config.deck_path);
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0)
    std::cout << "# hydrosoft: resolved configuration\n" << hs::format_config(config) << std::endl;
  const auto mesh = hs::load_mesh_on_rank_zero(config.mesh, PETSC_COMM_WORLD);
  hs::on_rank_zero(PETSC_COMM_WORLD, [&] {
    hs::check_groups(config, hs::groups_of(*mesh));
    hs::check_rigid_motions_held(config, mesh->node_groups, mesh->x, MPI_COMM_SELF);
    const auto exact = hs::make_exact_solution(config);
    hs::ExactValue exact_value;
    if (exact) {
      hs::check_reference_finite(config, *exact, mesh->x, MPI_COMM_SELF);
      exact_value = [&exact](const std::array<double, 3>& X, double s) {
        return exact->displacement(X, s);
      };
    }
    hs::check_boundary_conflicts(config, mesh->node_groups, mesh->x,
                                 static_cast<int64_t>(mesh->x.size() / 3), exact_value,
                                 MPI_COMM_SELF);
    std::vector<std::string> cavities;
    for (const auto& c : config.cavities) cavities.push_back(c.group);
    std::cout << "# hydrosoft: mesh " << config.mesh.file << "\n"
              << hs::format_statistics(hs::mesh_statistics(*mesh, cavities))
              << "# hydrosoft: the deck and its mesh are valid; nothing was solved" << std::endl;
  });
}

// hydrosoft mesh: the deck's mesh loaded (or meshed) and checked on rank 0 and written, whole
// or not at all, to `output`.
void write_mesh(const hs::Config& config, const std::string& output) {
  const auto mesh = hs::load_mesh_on_rank_zero(config.mesh, PETSC_COMM_WORLD);
  hs::on_rank_zero(PETSC_COMM_WORLD, [&] {
    hs::check_groups(config, hs::groups_of(*mesh));
    const std::string partial = output + ".partial";
    try {
      hs::write_mesh_h5(*mesh, partial);
      std::filesystem::rename(partial, output);
    } catch (...) {
      std::error_code ignored;
      std::filesystem::remove(partial, ignored);
      throw;
    }
    std::cout << "# hydrosoft: mesh " << config.mesh.file << " written to " << output << "\n"
              << hs::format_statistics(hs::mesh_statistics(*mesh, {})) << std::flush;
  });
}

}  // namespace

int main(int argc, char** argv) {
  // Separate hydrosoft's own arguments from PETSc's before PETSc sees them.
  hs::Arguments args;
  try {
    args = hs::parse_arguments(argc, argv);
  } catch (const hs::UsageError& e) {
    std::cerr << "hydrosoft: error: " << e.what() << "\n" << usage;
    return 2;
  }
  if (args.help) {
    std::cout << usage;
    return 0;
  }
  if (args.version) {
    std::cout << hs::version_text();
    return 0;
  }
  const std::string& deck = args.deck;
  const std::string& targets = args.targets;
  std::vector<std::string> overrides = args.overrides;
  if (args.quiet) overrides.push_back("output.progress=false");
  std::vector<char*> petsc_args = {argv[0]};
  for (auto& a : args.petsc) petsc_args.push_back(a.data());
  hs::InteractiveIo io;
  if (targets == "-") {
    const int answers = keep_stdout_for_answers();
    if (answers < 0) {
      std::cerr << "hydrosoft: error: --targets -: cannot set up standard output: "
                << std::strerror(errno) << std::endl;
      return 4;
    }
    io.write_line = [answers](const std::string& line) { return write_answer_line(answers, line); };
  }
  hs::use_one_scotch_thread();
  const std::string blas_threads = hs::limit_blas_threads();
  int pargc = static_cast<int>(petsc_args.size());
  petsc_args.push_back(nullptr);
  char** pargv = petsc_args.data();
  if (PetscInitialize(&pargc, &pargv, nullptr, usage)) return 1;
  hs::quiet_hdf5();  // every HDF5 failure is said in hydrosoft's one line
  // A reader that goes away (a client that closes its pipes, `| head`) makes a write fail
  // with EPIPE, which the writer handles, instead of SIGPIPE, which PETSc's handler turned
  // into a dump and exit 59 (set after PetscInitialize, which installs that handler).
  std::signal(SIGPIPE, SIG_IGN);
  if (deck.empty()) return fail(2, std::string("no deck given\n") + usage);
  if (args.verbose)
    for (const char* option : {"-snes_monitor", "-ksp_converged_reason", "-hs_bordered_monitor"})
      PetscOptionsSetValue(nullptr, option, nullptr);

  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  try {
    hs::Config config = hs::parse_deck(deck, overrides);
    if (!targets.empty()) {
      if (targets != "-") return fail(2, "--targets: only '-' (standard input) is supported");
      if (!config.control)
        return fail(2, deck + ": --targets - needs a deck with a control section");
      config.control->targets_from_stdin = true;
    }
    if (args.reduce) {
      if (!config.control)
        return fail(2, deck + ": hydrosoft reduce needs a deck with a control section");
      hs::TrainingConfig training;
      training.output = args.reduce_output;
      if (args.samples) training.samples = args.samples;
      if (args.design == "halton") training.design = hs::TrainingDesignKind::halton;
      if (args.pod_tolerance > 0) training.energy_tolerance = args.pod_tolerance;
      if (args.ecsw_tolerance > 0) training.ecsw_tolerance = args.ecsw_tolerance;
      config.training = training;
      config.control->reduced_model.clear();
      config.output.checkpoint.reset();  // training starts afresh
    }
    if (args.mesh) {
      write_mesh(config, args.mesh_output);
      PetscFinalize();
      return 0;
    }
    if (rank == 0) print_deck_warnings(config);
    if (args.check) {
      check_deck(config);
      PetscFinalize();
      return 0;
    }
    // With targets on standard input, standard output carries the JSON lines alone: the
    // resolved configuration and the summary go to standard error.
    std::ostream& report = targets.empty() ? std::cout : std::cerr;
    if (rank == 0)
      report << "# hydrosoft: resolved configuration\n"
             << hs::format_config(config) << "# BLAS threads per rank: " << blas_threads << "\n"
             << std::endl;
    // SIGTERM or SIGINT now stops the run at a step boundary, keeping what converged (set
    // after PetscInitialize, whose own SIGTERM handler it replaces; --check and mesh keep the
    // default: they have nothing to keep).
    hs::install_interrupt_handlers();
    const auto summary = hs::run_simulation(config, PETSC_COMM_WORLD, io, args.restart);
    if (rank == 0) report << hs::run_report(summary) << std::flush;
    if (rank == 0) report_unused(args.petsc_names);
  } catch (const hs::InputError& e) {
    // One line whatever bytes of a deck or mesh the message quotes (each reader escapes its
    // own; this is the net under them all).
    return fail(2, hs::printable(e.what()));
  } catch (const hs::SolveError& e) {
    return stopped(deck, e);
  } catch (const std::exception& e) {
    return fail(4, e.what());
  }
  PetscFinalize();
  return 0;
}
