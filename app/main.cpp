// hydrosoft: nonlinear FEM of soft robots driven by hydraulic and pneumatic cavities.
//
//   mpirun -np N build/bin/hydrosoft input/<deck>.yaml [--set key=value ...] [-petsc_option ...]
//
// The deck is validated before any work and printed resolved; --set overrides a deck key
// (e.g. --set mesh.order=2); every PETSc option can be given on the command line and wins
// over the deck's solver.petsc_options.
#include <petscsys.h>

#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "deck/deck.hpp"
#include "solvers/simulation.hpp"

namespace {

const char* usage =
    "usage: hydrosoft DECK.yaml [--set key=value ...] [--targets -] [PETSc options]\n"
    "  --set key=value   override a deck key, e.g. --set mesh.order=2 --set mesh.parameters.h=0.1\n"
    "  --targets -       read control targets from standard input, one per line: 'x y z' or\n"
    "                    'effector x y z'; each is answered with one JSON line\n"
    "  PETSc options     e.g. -snes_monitor -ksp_type cg -pc_type gamg (they win over the deck)\n";

int fail(int code, const std::string& message) {
  int rank = 0, size = 1;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  if (rank == 0 || code == 4) std::cerr << "hydrosoft: error: " << message << std::endl;
  if (size > 1 && code == 4) MPI_Abort(PETSC_COMM_WORLD, code);  // a rank-local failure
  PetscFinalize();
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  // Separate hydrosoft's own arguments from PETSc's before PETSc sees them.
  std::string deck, targets;
  std::vector<std::string> overrides;
  std::vector<char*> petsc_args = {argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--set") == 0 && i + 1 < argc) {
      overrides.emplace_back(argv[++i]);
    } else if (std::strcmp(argv[i], "--targets") == 0 && i + 1 < argc) {
      targets = argv[++i];
    } else if (std::strcmp(argv[i], "--help") == 0) {
      std::cout << usage;
      return 0;
    } else if (argv[i][0] != '-' && deck.empty()) {
      deck = argv[i];
    } else {
      petsc_args.push_back(argv[i]);
    }
  }
  int pargc = static_cast<int>(petsc_args.size());
  petsc_args.push_back(nullptr);
  char** pargv = petsc_args.data();
  if (PetscInitialize(&pargc, &pargv, nullptr, usage)) return 1;
  if (deck.empty()) return fail(2, std::string("no deck given\n") + usage);

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
    // With targets on standard input, standard output carries the answers: the resolved
    // configuration goes to standard error.
    if (rank == 0)
      (targets.empty() ? std::cout : std::cerr) << "# hydrosoft: resolved configuration\n"
                                                << hs::format_config(config) << std::endl;
    const auto summary = hs::run_simulation(config, PETSC_COMM_WORLD);
    if (rank == 0) {
      std::cout << "# hydrosoft: done\n" << summary.dump(2) << std::endl;
    }
  } catch (const hs::InputError& e) {
    return fail(2, e.what());
  } catch (const hs::SolveError& e) {
    return fail(3, e.what());
  } catch (const std::exception& e) {
    return fail(4, e.what());
  }
  PetscFinalize();
  return 0;
}
