// hydrosoft's command line: its own arguments apart from PETSc's, strictly. Any argument that
// is neither hydrosoft's (DECK, --set key=value, --targets -, --restart FOLDER, --check,
// --help/-h, --version) nor a
// PETSc option (-name, or -name value) is an error that names it; nothing is silently ignored.
// `hydrosoft mesh DECK.yaml OUT.h5` (the word mesh first) meshes the deck's mesh once into a
// hydrosoft mesh file that runs then read in parallel. `hydrosoft reduce DECK -o MODEL.h5
// [--samples N] [--pod-tolerance E] [--ecsw-tolerance T]` trains a reduced-order model of a
// control deck (docs/reduced_models.md).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace hs {

struct Arguments {
  std::string deck;
  std::vector<std::string> overrides;  // of --set, in order
  std::string targets;                 // of --targets ("" when not given)
  std::string restart;                 // of --restart: a run's folder with checkpoint.h5
  bool help = false, version = false;
  bool quiet = false;              // -q: no progress lines (output.progress = false)
  bool verbose = false;            // -v: the solvers' monitors (SNES, KSP, the cavities' Newton)
  bool check = false;              // --check: validate the deck and its mesh, solve nothing
  bool mesh = false;               // hydrosoft mesh DECK OUT.h5: write the mesh, solve nothing
  std::string mesh_output;         // its OUT.h5
  bool reduce = false;             // hydrosoft reduce DECK -o MODEL.h5: train a reduced model
  std::string reduce_output;       // its MODEL.h5
  int samples = 0;                 // --samples N (0: the default)
  std::string design;              // --design grid|halton (empty: grid)
  double pod_tolerance = 0;        // --pod-tolerance E (0: the default)
  double ecsw_tolerance = 0;       // --ecsw-tolerance T (0: the default)
  std::vector<std::string> petsc;  // PETSc's arguments, in order (values included)
  std::vector<std::string> petsc_names;  // the PETSc options among them, e.g. "-snes_monitor"
};

// A command line that cannot be read: the message names the argument and the reason.
class UsageError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// argv[1..argc) split and checked; throws UsageError.
Arguments parse_arguments(int argc, const char* const* argv);

}  // namespace hs
