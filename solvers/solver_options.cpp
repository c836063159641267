#include "solvers/solver_options.hpp"

#include <petscsnes.h>

#include <algorithm>
#include <cctype>
#include <sstream>
#include <stdexcept>

#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "solvers/mixed_factor.hpp"
#include "solvers/petsc_check.hpp"
#include "solvers/petsc_handle.hpp"

namespace hs {
namespace {

std::vector<PetscOptions> pushed_databases;  // by OptionsScope, innermost last

bool name_ends_with(const std::string& name, const std::string& suffix) {
  return name.size() >= suffix.size() &&
         name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Whether `type` is a registered type of the object kind that option `name` sets (by its
// suffix); true for options of other kinds, which PETSc checks when they are used.
bool known_type(const std::string& name, const std::string& type) {
  // Errors come back as codes, without PETSc's printed trace.
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  PetscErrorCode error = 0;
  if (name_ends_with(name, "linesearch_type")) {
    LineSearchHandle ls;
    SNESLineSearchCreate(PETSC_COMM_SELF, ls.out());
    error = SNESLineSearchSetType(ls, type.c_str());
  } else if (name_ends_with(name, "snes_type")) {
    SnesHandle snes;
    SNESCreate(PETSC_COMM_SELF, snes.out());
    error = SNESSetType(snes, type.c_str());
  } else if (name_ends_with(name, "ksp_type")) {
    KspHandle ksp;
    KSPCreate(PETSC_COMM_SELF, ksp.out());
    error = KSPSetType(ksp, type.c_str());
  } else if (name_ends_with(name, "pc_type")) {
    PcHandle pc;
    PCCreate(PETSC_COMM_SELF, pc.out());
    error = PCSetType(pc, type.c_str());
  } else if (name_ends_with(name, "mat_partitioning_type")) {
    MatPartitioningHandle partitioning;
    MatPartitioningCreate(PETSC_COMM_SELF, partitioning.out());
    error = MatPartitioningSetType(partitioning, type.c_str());
  }  // each object is released in its branch, still under the return handler
  PetscPopErrorHandler();
  return error == 0;
}

// The entries of the global database (the command line, and what main adds for --verbose):
// names without the dash, "" for a flag. PETSc lists them as one string; a token is a name
// where PETSc's own parser takes it for one (a dash and a letter: "-1" is a value).
std::vector<std::pair<std::string, std::string>> global_entries() {
  char* all = nullptr;
  HS_PETSC(PetscOptionsGetAll(nullptr, &all));
  std::istringstream in(all ? all : "");
  HS_PETSC(PetscFree(all));
  std::vector<std::pair<std::string, std::string>> entries;
  std::string token;
  while (in >> token) {
    const size_t dashes = token.rfind("--", 0) == 0 ? 2 : 1;
    if (token[0] == '-' && token.size() > dashes &&
        std::isalpha(static_cast<unsigned char>(token[dashes]))) {
      entries.emplace_back(token.substr(dashes), "");
    } else if (!entries.empty()) {  // a value, or a further word of one
      std::string& value = entries.back().second;
      value += (value.empty() ? "" : " ") + token;
    }
  }
  return entries;
}

// The solver object an option belongs to: the longest of the prefixes that begins it, or ""
// for an option of every object.
std::string owner_of(const std::string& name) {
  std::string owner;
  for (const char* prefix : kSolverPrefixes)
    if (name.rfind(prefix, 0) == 0 && std::string(prefix).size() > owner.size()) owner = prefix;
  return owner;
}

// Why the option `name` (without its dash) is not hydrosoft's, or "" where it is hydrosoft's
// or PETSc's; `dash` is how the message spells an option ("-" on the command line).
std::string unknown_option_problem(const std::string& name, const std::string& dash) {
  if (name.rfind("hs_", 0) != 0 || !owner_of(name).empty()) return "";
  std::vector<std::string> known(std::begin(kUnprefixedOptions), std::end(kUnprefixedOptions));
  if (contains(known, name)) return "";
  // The nearest of every prefix put in place of every beginning of the name (and of the
  // options without a prefix): -hs_bordred_ksp_type is nearest -hs_bordered_ksp_type.
  std::vector<std::string> prefixes;
  for (const char* prefix : kSolverPrefixes) {
    prefixes.emplace_back(prefix);
    for (size_t begin = 1; begin <= name.size(); ++begin)
      known.push_back(prefix + name.substr(begin));
  }
  return "unknown hydrosoft option prefix (did you mean " + dash + nearest(name, known) +
         "? the solver objects' prefixes are " + join(prefixes) +
         "; docs/decks.md, \"Solver options\")";
}

void set_value(PetscOptions db, const std::string& name, const std::string& value) {
  HS_PETSC(PetscOptionsSetValue(db, ("-" + name).c_str(), value.empty() ? nullptr : value.c_str()));
}

}  // namespace

std::map<std::string, std::string> preset_options(SolverPreset preset, TangentKind tangent) {
  // Convergence is judged on the residual (never on a small step alone: a stalled
  // iterative solve would otherwise look converged). No divergence tolerance: a full Newton
  // step from rest can raise the residual by more than PETSc's default factor 1e4 before it
  // converges (the 1M-dof cantilever: x1.2e4 after its first step, then 5 more to 1e-8,
  // where the default stopped it and cost a cutback and 6 iterations); a step that truly
  // diverges is stopped by snes_max_it, an inverted element or a non-finite residual, and cut
  // back.
  std::map<std::string, std::string> options = {
      {"snes_type", "newtonls"}, {"snes_linesearch_type", "basic"},   {"snes_rtol", "1e-8"},
      {"snes_stol", "0"},        {"snes_divergence_tolerance", "-1"}, {"snes_max_it", "30"}};
  switch (preset) {
    case SolverPreset::mumps:
      options["ksp_type"] = "preonly";
      // A symmetric tangent is factored as L D L^T (MUMPS's general symmetric mode, with
      // pivoting, so an indefinite tangent near a limit point is fine): ~30% less time than LU.
      options["pc_type"] = tangent.symmetric ? "cholesky" : "lu";
      options["pc_factor_mat_solver_type"] = "mumps";
      // A nodal-pressure body's tangent reaches its nodes' neighbours' neighbours; its mixed
      // system's factors are about a third smaller (docs/formulation.md).
      if (tangent.nodal_pressure) {
        register_mixed_factor();
        options["pc_type"] = kMixedFactorType;
        options["pc_mixed_factor_type"] = tangent.symmetric ? "cholesky" : "lu";
        options.erase("pc_factor_mat_solver_type");
        // MUMPS's own choice of ordering took AMF on the finger's mixed system, whose
        // factors then had 3.06M entries against PORD's 1.76M (on the sphere it took PORD).
        options["mat_mumps_icntl_7"] = "4";
      }
      break;
    case SolverPreset::gamg:
      // MINRES for a symmetric tangent that may be indefinite (GAMG's smoothers keep the
      // preconditioner definite): a finite-strain Newton iterate past the solution meets one,
      // and CG stopping there cost a load-step cutback.
      options["ksp_type"] = !tangent.symmetric ? "gmres" : tangent.definite ? "cg" : "minres";
      options["pc_type"] = "gamg";
      options["ksp_rtol"] = "1e-10";
      options["ksp_max_it"] = "2000";
      options["pc_gamg_threshold"] = "0.01";
      options["mg_levels_ksp_type"] = "chebyshev";
      options["mg_levels_pc_type"] = "jacobi";
      break;
  }
  return options;
}

void check_solver_options(const SolverConfig& solver, const std::string& deck_path) {
  register_mixed_factor();  // a type of hydrosoft's own, which a deck or command line may name
  const auto command_line = global_entries();
  for (const auto& [name, value] : solver.petsc_options)
    if (const std::string problem = unknown_option_problem(name, ""); !problem.empty())
      throw InputError(deck_path + ": solver.petsc_options." + name + ": " + problem);
  for (const auto& [name, value] : command_line)
    if (const std::string problem = unknown_option_problem(name, "-"); !problem.empty())
      throw InputError("command line: -" + name + ": " + problem);
  for (const auto& [name, value] : solver.petsc_options)
    if (!known_type(name, value))
      throw InputError(deck_path + ": solver.petsc_options." + name + ": unknown PETSc type '" +
                       value + "'");
  for (const auto& [name, value] : command_line)
    if (!known_type(name, value))
      throw InputError("command line: -" + name + ": unknown PETSc type '" + value + "'");
}

SolverOptions::SolverOptions(std::string prefix, const SolverConfig& solver,
                             const std::map<std::string, std::string>& preset, Reach reach)
    : prefix_(std::move(prefix)) {
  // The command line is read from PETSc's default database: inside an OptionsScope that is
  // another object's.
  if (!pushed_databases.empty())
    throw std::logic_error("solver options " + prefix_ + " composed inside an OptionsScope");
  const auto command_line = global_entries();
  // name (without prefix) -> value and the command-line option it came from ("" if none).
  std::map<std::string, std::pair<std::string, std::string>> own;
  const bool every = reach == Reach::every_object;
  if (every)
    for (const auto& [name, value] : preset) own[name] = {value, ""};
  // Within a source, the key with the object's prefix wins over the unprefixed one.
  auto add = [&](const auto& entries, bool from_command_line) {
    for (int prefixed = 0; prefixed < 2; ++prefixed)
      for (const auto& [name, value] : entries) {
        const std::string owner = owner_of(name);
        if (prefixed ? owner != prefix_ : !(every && owner.empty())) continue;
        own[name.substr(owner.size())] = {value, from_command_line ? name : ""};
      }
  };
  add(solver.petsc_options, false);
  add(command_line, true);

  HS_PETSC(PetscOptionsCreate(&db_));
  // First what the global database held before objects had their own (the command line over
  // the deck, unprefixed and as typed), for what PETSc reads without the object's prefix
  // inside an OptionsScope (a matrix's -mat_view) and the names kept from then; then the
  // object's own options under its prefix.
  for (const auto& [name, value] : solver.petsc_options) set_value(db_, name, value);
  for (const auto& [name, value] : command_line) {
    set_value(db_, name, value);
    copied_.emplace_back(name, name);
  }
  for (const auto& [name, source] : own) {
    set_value(db_, prefix_ + name, source.first);
    if (!source.second.empty()) copied_.emplace_back(prefix_ + name, source.second);
  }
}

SolverOptions::~SolverOptions() {
  // A destructor does not throw: errors here leave a warning unsaid at worst. Inside a scope
  // (an exception on its way out of one) the global database is not the default: nothing is
  // marked.
  for (const auto& [here, global] : copied_) {
    PetscBool used = PETSC_FALSE, set = PETSC_FALSE;
    if (pushed_databases.empty() && PetscOptionsUsed(db_, here.c_str(), &used) == 0 && used)
      PetscOptionsHasName(nullptr, nullptr, ("-" + global).c_str(), &set);  // marks it used
  }
  PetscOptionsDestroy(&db_);
}

void SolverOptions::attach(PetscObject object) const {
  HS_PETSC(PetscObjectSetOptions(object, db_));
}

bool SolverOptions::has(const std::string& name) const {
  PetscBool set = PETSC_FALSE;
  HS_PETSC(PetscOptionsHasName(db_, prefix_.c_str(), ("-" + name).c_str(), &set));
  return set;
}

PetscInt SolverOptions::get_int(const std::string& name, PetscInt fallback) const {
  HS_PETSC(PetscOptionsGetInt(db_, prefix_.c_str(), ("-" + name).c_str(), &fallback, nullptr));
  return fallback;
}

double SolverOptions::get_real(const std::string& name, double fallback) const {
  PetscReal value = fallback;
  HS_PETSC(PetscOptionsGetReal(db_, prefix_.c_str(), ("-" + name).c_str(), &value, nullptr));
  return value;
}

std::string SolverOptions::get_string(const std::string& name, const std::string& fallback) const {
  char value[256];
  PetscBool set = PETSC_FALSE;
  HS_PETSC(
      PetscOptionsGetString(db_, prefix_.c_str(), ("-" + name).c_str(), value, sizeof value, &set));
  return set ? std::string(value) : fallback;
}

bool SolverOptions::factors_mixed() const { return get_string("pc_type", "") == kMixedFactorType; }

bool SolverOptions::get_bool(const std::string& name, bool fallback) const {
  PetscBool value = fallback ? PETSC_TRUE : PETSC_FALSE;
  HS_PETSC(PetscOptionsGetBool(db_, prefix_.c_str(), ("-" + name).c_str(), &value, nullptr));
  return value;
}

bool SolverOptions::get_unprefixed_bool(const std::string& name, bool fallback) const {
  PetscBool value = fallback ? PETSC_TRUE : PETSC_FALSE;
  HS_PETSC(PetscOptionsGetBool(db_, nullptr, ("-" + name).c_str(), &value, nullptr));
  return value;
}

OptionsScope::OptionsScope(PetscOptions database) { push(database); }

OptionsScope::OptionsScope(PetscObject object) {
  PetscOptions database = nullptr;
  HS_PETSC(PetscObjectGetOptions(object, &database));
  push(database);
}

void OptionsScope::push(PetscOptions database) {
  // PETSc chains a pushed database to the one below it: pushing one twice would break the chain.
  if (!database || std::find(pushed_databases.begin(), pushed_databases.end(), database) !=
                       pushed_databases.end())
    return;
  HS_PETSC(PetscOptionsPush(database));
  pushed_databases.push_back(database);
  pushed_ = true;
}

OptionsScope::~OptionsScope() {
  if (!pushed_) return;
  PetscOptionsPop();
  pushed_databases.pop_back();
}

}  // namespace hs
