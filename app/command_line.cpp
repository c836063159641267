#include "command_line.hpp"

#include <cctype>
#include <cstring>

namespace hs {
namespace {

const char* const kOwnOptions[] = {"--set",     "--targets", "--restart", "--check",   "--help",
                                   "--version", "--quiet",   "--verbose", "--samples", "--design"};

// A PETSc option is -name with a letter first; "-5" or "-1e3" is a (negative) value.
bool is_petsc_option(const std::string& a) {
  return a.size() > 1 && a[0] == '-' && a[1] != '-' &&
         std::isalpha(static_cast<unsigned char>(a[1]));
}

// The own option nearest to a mistyped one (--sett, --target), or "".
std::string nearest_own(const std::string& a) {
  for (const char* own : kOwnOptions) {
    const std::string o = own;
    const size_t common = std::min(a.size(), o.size());
    if (a.compare(0, common, o, 0, common) == 0) return o;
  }
  return "";
}

}  // namespace

Arguments parse_arguments(int argc, const char* const* argv) {
  Arguments args;
  auto value_of = [&](int& i, const std::string& option) {
    if (i + 1 >= argc || std::strncmp(argv[i + 1], "--", 2) == 0)
      throw UsageError(option + ": needs a value" +
                       (option == "--set"       ? " (--set key=value)"
                        : option == "--restart" ? " (--restart FOLDER, a run's output folder)"
                                                : " (--targets -)"));
    return std::string(argv[++i]);
  };
  bool after_petsc_option = false;  // the previous argument was -name: a bare word is its value
  int first = 1;
  if (argc > 1 && std::strcmp(argv[1], "mesh") == 0) {
    args.mesh = true;
    first = 2;
  } else if (argc > 1 && std::strcmp(argv[1], "reduce") == 0) {
    args.reduce = true;
    first = 2;
  }
  for (int i = first; i < argc; ++i) {
    const std::string a = argv[i];
    const bool was_after_option = after_petsc_option;
    after_petsc_option = false;
    if (a == "--set") {
      const std::string v = value_of(i, a);
      if (v.find('=') == std::string::npos)
        throw UsageError("--set " + v + ": expected key=value, e.g. --set mesh.order=2");
      args.overrides.push_back(v);
    } else if (args.reduce && a == "-o") {
      if (i + 1 >= argc) throw UsageError("reduce: -o needs a value (-o MODEL.h5)");
      args.reduce_output = argv[++i];
    } else if (a == "--samples") {
      if (!args.reduce) throw UsageError("--samples: only for hydrosoft reduce");
      const std::string v = value_of(i, a);
      try {
        size_t used = 0;
        args.samples = std::stoi(v, &used);
        if (used != v.size()) throw std::invalid_argument(v);
      } catch (const std::exception&) {
        throw UsageError("--samples " + v + ": expected a whole number, e.g. --samples 17");
      }
      if (args.samples < 3 || args.samples > 1000)
        throw UsageError("--samples " + v + ": between 3 and 1000");
    } else if (a == "--design") {
      if (!args.reduce) throw UsageError("--design: only for hydrosoft reduce");
      args.design = value_of(i, a);
      if (args.design != "grid" && args.design != "halton")
        throw UsageError("--design " + args.design + ": grid or halton");
    } else if (a == "--pod-tolerance" || a == "--ecsw-tolerance") {
      if (!args.reduce) throw UsageError(a + ": only for hydrosoft reduce");
      const std::string v = value_of(i, a);
      double t = 0;
      try {
        size_t used = 0;
        t = std::stod(v, &used);
        if (used != v.size()) throw std::invalid_argument(v);
      } catch (const std::exception&) {
        throw UsageError(a + " " + v + ": expected a number, e.g. " + a + " 1e-6");
      }
      if (!(t > 0 && t < 1)) throw UsageError(a + " " + v + ": between 0 and 1, both excluded");
      (a == "--pod-tolerance" ? args.pod_tolerance : args.ecsw_tolerance) = t;
    } else if (a == "--targets") {
      args.targets = value_of(i, a);
    } else if (a == "--restart") {
      if (!args.restart.empty()) throw UsageError("--restart: given twice");
      args.restart = value_of(i, a);
    } else if (a == "--help" || a == "-h" || a == "-help") {
      args.help = true;
    } else if (a == "--version") {
      args.version = true;
    } else if (a == "--check") {
      args.check = true;
    } else if (a == "-q" || a == "--quiet") {
      args.quiet = true;
    } else if (a == "-v" || a == "--verbose") {
      args.verbose = true;
    } else if (a.rfind("--", 0) == 0) {
      const std::string near = nearest_own(a);
      throw UsageError("unknown argument '" + a + "'" +
                       (near.empty() ? "" : " (did you mean " + near + "?)") +
                       "; PETSc options take one dash, e.g. -snes_monitor");
    } else if (is_petsc_option(a)) {
      args.petsc.push_back(a);
      args.petsc_names.push_back(a);
      after_petsc_option = true;
    } else if (args.deck.empty() && (a.size() > 5 && (a.rfind(".yaml") == a.size() - 5 ||
                                                      a.rfind(".yml") == a.size() - 4))) {
      args.deck = a;  // a deck, even right after a PETSc flag (-snes_monitor deck.yaml)
    } else if (args.mesh && !args.deck.empty() && args.mesh_output.empty() && a.size() > 3 &&
               a.rfind(".h5") == a.size() - 3) {
      args.mesh_output = a;
    } else if (was_after_option) {
      args.petsc.push_back(a);  // the value of the PETSc option before it
    } else if (args.deck.empty()) {
      args.deck = a;
    } else {
      throw UsageError(
          "unexpected argument '" + a + "' after the deck " + args.deck +
          (a.find('=') != std::string::npos ? " (to override a key: --set " + a + ")" : ""));
    }
  }
  if (args.mesh && (args.deck.empty() || args.mesh_output.empty()))
    throw UsageError("mesh: usage: hydrosoft mesh DECK.yaml OUT.h5 [--set key=value ...]");
  if (args.mesh && (args.check || !args.targets.empty() || !args.restart.empty()))
    throw UsageError("mesh: --check, --targets and --restart do not apply (it solves nothing)");
  if (args.reduce && (args.deck.empty() || args.reduce_output.empty()))
    throw UsageError(
        "reduce: usage: hydrosoft reduce DECK.yaml -o MODEL.h5 [--samples N] [--design D] "
        "[--set key=value ...]");
  if (args.reduce && (args.check || !args.targets.empty() || !args.restart.empty()))
    throw UsageError("reduce: --check, --targets and --restart do not apply (it trains a model)");
  if (args.check && !args.restart.empty())
    throw UsageError("--check: --restart does not apply (it solves nothing)");
  return args;
}

}  // namespace hs
