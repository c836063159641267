// The PETSc options of each solver object (docs/decks.md, "Solver options"). Every object has
// its own prefix and its own options database, composed when it is made from, lowest
// precedence first: the preset, the deck's solver.petsc_options (an unprefixed key for every
// object, a key with an object's prefix for that one), the command line's unprefixed options
// and the command line's options with the object's prefix. PETSc's global database (the
// command line) is only read: nothing of the preset or the deck is written into it.
#pragma once

#include <petscsys.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "deck/config.hpp"

namespace hs {

// The prefixes of the solver objects: the plain Newton's SNES (its KSP, PC and line search
// included), the bordered Newton (its KSP and its own Newton parameters), the inverse
// controller's KSP, the controller's background correction KSP, the dynamic stepping's
// mass solve (its matrix included), the mesh's partitioner over the ranks.
inline constexpr const char* kNewtonPrefix = "hs_newton_";
inline constexpr const char* kBorderedPrefix = "hs_bordered_";
inline constexpr const char* kControlPrefix = "hs_control_";
inline constexpr const char* kCorrectionPrefix = "hs_control_correction_";
inline constexpr const char* kMassPrefix = "hs_mass_";
inline constexpr const char* kPartitionPrefix = "hs_partition_";
// Every object's prefix: the one list that the composition of an object's options and the
// check of option names (check_solver_options) read. A new solver object adds its line here.
inline constexpr const char* kSolverPrefixes[] = {kNewtonPrefix,  kBorderedPrefix,
                                                  kControlPrefix, kCorrectionPrefix,
                                                  kMassPrefix,    kPartitionPrefix};
// hydrosoft's options that no object's prefix begins (read with get_unprefixed_bool).
inline constexpr const char* kUnprefixedOptions[] = {"hs_near_null_space", "hs_volume_monitor"};

// What the preset needs to know of the tangent: symmetric (L D L^T, CG or MINRES), positive
// definite (CG), and with a nodal-pressure body (MUMPS factors its mixed system,
// solvers/mixed_factor.hpp).
struct TangentKind {
  bool symmetric = true;
  bool definite = true;
  bool nodal_pressure = false;
};

// The preset's options for a tangent of this kind, without prefix.
std::map<std::string, std::string> preset_options(SolverPreset preset, TangentKind tangent);

// Before any work, for every option of the deck's solver.petsc_options and of the command
// line: one that begins with "hs_" must begin with an object's prefix (kSolverPrefixes) or be
// one of kUnprefixedOptions, where a misspelt prefix would otherwise leave the option unread
// without a word; and PETSc is asked whether every *_type option (with or without an object's
// prefix) names a type it has (KSP, PC, SNES, line search, mesh partitioner). Throws InputError
// naming the deck key or the command-line option, and for a prefix the nearest known one.
void check_solver_options(const SolverConfig& solver, const std::string& deck_path);

class SolverOptions {
 public:
  // Whether the unprefixed options of the deck and the command line (and the preset) reach the
  // object, or only those with its prefix (the objects that set their own solver in code).
  enum class Reach { every_object, own_prefix_only };

  // Collective on nothing: each rank composes its own copy.
  SolverOptions(std::string prefix, const SolverConfig& solver,
                const std::map<std::string, std::string>& preset, Reach reach);
  // Marks in the global database the command-line options this object used, so that
  // -options_left and hydrosoft's "was not used" warning see them used.
  ~SolverOptions();
  SolverOptions(const SolverOptions&) = delete;
  SolverOptions& operator=(const SolverOptions&) = delete;

  const std::string& prefix() const { return prefix_; }
  PetscOptions database() const { return db_; }
  // Gives the object this database (before its XSetOptionsPrefix and XSetFromOptions); the
  // sub-objects it makes (a SNES's KSP, PC, line search) take it from there.
  void attach(PetscObject object) const;
  // The object's option `name` (without prefix or dash).
  bool has(const std::string& name) const;
  PetscInt get_int(const std::string& name, PetscInt fallback) const;
  double get_real(const std::string& name, double fallback) const;
  bool get_bool(const std::string& name, bool fallback) const;
  std::string get_string(const std::string& name, const std::string& fallback) const;
  // Whether the object's tangent is factored through its mixed system (pc_type hs_mixed,
  // solvers/mixed_factor.hpp): its matrix then needs that system beside it.
  bool factors_mixed() const;
  // An option read without the object's prefix (-hs_near_null_space): the command line's, or
  // else the deck's, as the global database held it before objects had their own.
  bool get_unprefixed_bool(const std::string& name, bool fallback) const;

 private:
  std::string prefix_;
  PetscOptions db_ = nullptr;
  // Pairs (name in this database, name in the global one) of the command-line options
  // copied here.
  std::vector<std::pair<std::string, std::string>> copied_;
};

// While it lives, `database` (or the object's own database) is PETSc's default database.
// PETSc's MUMPS factor and the smoothers GAMG makes for its levels read the default database,
// not their parent's, when the KSP is set up; a set-up or solve inside this scope gives them
// the object's options. Nested scopes of one database push it once.
class OptionsScope {
 public:
  explicit OptionsScope(PetscOptions database);
  explicit OptionsScope(PetscObject object);
  ~OptionsScope();
  OptionsScope(const OptionsScope&) = delete;
  OptionsScope& operator=(const OptionsScope&) = delete;

 private:
  void push(PetscOptions database);
  bool pushed_ = false;
};

}  // namespace hs
