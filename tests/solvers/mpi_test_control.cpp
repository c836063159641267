// The inverse controller against forward simulations, on 1 and 2 ranks: a target that a
// forward run reaches with a known pressure is reached to 0.1 mm with that pressure, by the
// pneumatic and by the hydraulic cylinder (the liquid's weight acting through the unified
// constraint); a target beyond the pressure bound ends on the forward run at the bound, with
// the actuator marked saturated; so does the pneumatic cylinder of an exactly incompressible
// silicone. Each solver object takes its own options (its prefix) and
// the shared ones, and its MUMPS factor takes them too.
#include <gtest/gtest.h>
#include <petscsnes.h>

#include <cmath>
#include <filesystem>

#include "control_scene.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/multi_solve.hpp"

namespace {
namespace mpi_test_control {

// A cylinder with its cavity as the actuator, the effector at the centre of the free end
// (the coarse compressible cylinder of ../mpi_test_decks.hpp).
struct Scene : hs_test::ControlScene {
  Scene(const std::string& deck, double max_pressure,
        const std::vector<std::string>& overrides = {})
      : ControlScene(deck, {0.0, 0.0, -0.15}, actuator(max_pressure),
                     hs_test::coarse_cylinder(overrides)) {}
  static hs::ActuatorConfig actuator(double max_pressure) {
    hs::ActuatorConfig a;
    a.constraint = "cavity";
    a.max_multiplier = max_pressure;
    return a;
  }
};

void expect_reaches(const std::string& deck, const std::string& free_solve = "newton",
                    int refactor_every = 1, const std::vector<std::string>& overrides = {}) {
  Scene s(deck, 1e300, overrides);
  s.config.control->free_solve = hs::enum_of<hs::FreeSolve>(hs::kFreeSolveNames, free_solve);
  s.config.control->refactor_every = refactor_every;
  const double p = 3000;
  const auto target = s.forward(p);
  std::vector<double> x;  // the equilibrium at the final actuation (one_step reports a prediction)
  const hs::ControlStepReport r = s.drive(target, 8, &x);
  EXPECT_LT(r.error, 1e-4) << deck;
  double error2 = 0;
  for (int d = 0; d < 3; ++d) error2 += std::pow(x[d] - target[d], 2);
  EXPECT_LT(std::sqrt(error2), 1e-4) << deck << " " << free_solve << " " << refactor_every;
  EXPECT_NEAR(r.actuation[0], p, 0.01 * p) << deck;
  EXPECT_FALSE(r.saturated[0]);
  EXPECT_TRUE(r.qp_solved);
  EXPECT_LT(r.kkt_residual, 1e-8);
}

TEST(Control, PneumaticCylinderReachesAForwardRunsTarget) { expect_reaches("cylinder_air.yaml"); }

TEST(Control, HydraulicCylinderReachesAForwardRunsTarget) { expect_reaches("cylinder_water.yaml"); }

TEST(Control, ExactlyIncompressibleCylinderReachesAForwardRunsTarget) {
  // nu = 0.5 on P1 and P2: the controller's equilibrium solves keep every patch's (element's)
  // volume through their multipliers, as the forward run's do.
  expect_reaches("cylinder_air.yaml", "newton", 1, {"materials[0].nu=0.5"});
  expect_reaches("cylinder_air.yaml", "newton", 1, {"materials[0].nu=0.5", "mesh.order=2"});
}

TEST(Control, OneLinearisationPerStepReachesTheTargetToo) {
  // The paper's real-time step (one assembly and factorization for the free motion and the
  // compliance), and the same with the factorization kept for three steps.
  expect_reaches("cylinder_water.yaml", "one_step", 1);
  expect_reaches("cylinder_water.yaml", "one_step", 3);
}

TEST(Control, UnreachableTargetSaturatesAtTheBound) {
  const double bound = 2000;
  Scene s("cylinder_air.yaml", bound);
  const auto at_bound = s.forward(bound);
  const auto beyond = s.forward(2.5 * bound);
  const hs::ControlStepReport r = s.drive(beyond, 8);
  EXPECT_NEAR(r.actuation[0], bound, 1e-6 * bound);
  EXPECT_TRUE(r.saturated[0]);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(r.reached[d], at_bound[d], 1e-4) << d;
  EXPECT_GT(r.error, 1e-3);  // the target really is out of reach
}

// The value of option `name` of the object's own database, as PETSc reads it for the object.
std::string option_of(KSP ksp, const char* name) {
  PetscOptions db = nullptr;
  PetscObjectGetOptions(reinterpret_cast<PetscObject>(ksp), &db);
  const char* prefix = nullptr;
  KSPGetOptionsPrefix(ksp, &prefix);
  char value[64] = "";
  PetscOptionsGetString(db, prefix, name, value, sizeof value, nullptr);
  return value;
}

TEST(SolverObjectOptions, EachObjectTakesItsPrefixedOptionsAndTheSharedOnes) {
  // As if on the command line: an option of the controller's KSP alone, and one of every object.
  PetscOptionsSetValue(nullptr, "-hs_control_ksp_type", "gmres");
  PetscOptionsSetValue(nullptr, "-ksp_max_it", "23");
  PetscOptionsSetValue(nullptr, "-hs_newton_ksp_type", "bcgs");  // no plain Newton here
  {
    hs_test::DeckProblem scene(
        "cylinder_air.yaml", hs_test::coarse_cylinder(), [](hs::Config& config) {
          hs::ControlConfig control;
          control.effectors = {hs::EffectorConfig{"tip", "", {0.0, 0.0, -0.15}}};
          hs::ActuatorConfig actuator;
          actuator.constraint = "cavity";
          control.actuators = {actuator};
          control.free_solve = hs::FreeSolve::one_step;
          control.factor_threads = 1;  // the background correction too
          config.control = control;
          config.solver.petsc_options = {{"ksp_max_it", "17"},
                                         {"ksp_rtol", "1e-3"},
                                         {"hs_control_ksp_rtol", "1e-4"},
                                         {"mat_mumps_icntl_14", "77"},
                                         {"hs_control_mat_mumps_icntl_14", "88"},
                                         {"hs_control_correction_ksp_rtol", "1e-2"}};
        });
    hs::ConstraintSet cavities(scene.config, *scene.problem);
    hs::BorderedNewton newton(*scene.problem, cavities, scene.config.solver, hs::TangentKind{});
    hs::Effectors effectors(scene.config, *scene.problem);
    hs::InverseController controller(scene.config, *scene.problem, cavities, newton, effectors);

    struct Expected {
      KSP ksp;
      const char *type, *pc, *rtol;
      int icntl_14;
    };
    // The bordered Newton's KSP keeps the preset (the controller's option does not reach it),
    // the deck's unprefixed rtol reaches it, the controller's prefixed one wins over it there;
    // the command line's max_it wins over the deck's in both. (A preonly KSP does not read its
    // tolerances: they are read from the object's database, as PETSc would.)
    for (const Expected& e : {Expected{newton.ksp(), "preonly", "cholesky", "1e-3", 77},
                              Expected{controller.ksp(), "gmres", "cholesky", "1e-4", 88}}) {
      KSPType type;
      KSPGetType(e.ksp, &type);
      EXPECT_STREQ(type, e.type);
      PC pc;
      KSPGetPC(e.ksp, &pc);
      PCType pc_type;
      PCGetType(pc, &pc_type);
      EXPECT_STREQ(pc_type, e.pc);
      EXPECT_EQ(option_of(e.ksp, "-ksp_rtol"), e.rtol);
      EXPECT_EQ(option_of(e.ksp, "-ksp_max_it"), "23");
      // The factor PETSc makes when the KSP is set up (inside the object's solve) takes the
      // object's options: MUMPS reads PETSc's default database, not its parent's.
      const hs::VecHandle u(scene.problem->create_vector()), b(scene.problem->create_vector()),
          x(scene.problem->create_vector());
      const hs::MatHandle J(scene.problem->create_matrix());
      ASSERT_TRUE(scene.problem->jacobian(u, 0.0, J));
      VecSet(b, 1.0);
      scene.problem->zero_constrained(b);
      KSPSetOperators(e.ksp, J, J);
      ASSERT_TRUE(hs::solve_columns(e.ksp, {b}, {x}));
      Mat F;
      PCFactorGetMatrix(pc, &F);
      PetscInt icntl = 0;
      MatMumpsGetIcntl(F, 14, &icntl);
      EXPECT_EQ(icntl, e.icntl_14);
    }
    PetscReal rtol = 0;
    PetscInt max_it = 0;
    KSPGetTolerances(controller.ksp(), &rtol, nullptr, nullptr, &max_it);
    EXPECT_DOUBLE_EQ(rtol, 1e-4);
    EXPECT_EQ(max_it, 23);
    // The background correction sets its own solver: its prefixed option reaches it, the
    // unprefixed ones do not (GMRES, at most 50 iterations, as set in code).
    ASSERT_NE(controller.background(), nullptr);
    const hs::MatHandle J(scene.problem->create_matrix());
    KSP correction = controller.background()->correction(J);
    KSPGetTolerances(correction, &rtol, nullptr, nullptr, &max_it);
    EXPECT_DOUBLE_EQ(rtol, 1e-2);
    EXPECT_EQ(max_it, 50);
    KSPType type;
    KSPGetType(correction, &type);
    EXPECT_STREQ(type, "gmres");
  }
  // Nothing of the preset or the deck went into the global database, and the options the
  // objects used are marked used there (-options_left, the "was not used" warning).
  for (const char* name :
       {"-ksp_type", "-pc_type", "-snes_rtol", "-ksp_rtol", "-mat_mumps_icntl_14",
        "-hs_control_ksp_rtol", "-pc_factor_mat_solver_type"}) {
    PetscBool set = PETSC_TRUE;
    PetscOptionsHasName(nullptr, nullptr, name, &set);
    EXPECT_FALSE(set) << name;
  }
  PetscBool used = PETSC_FALSE;
  PetscOptionsUsed(nullptr, "hs_control_ksp_type", &used);
  EXPECT_TRUE(used);
  PetscOptionsUsed(nullptr, "ksp_max_it", &used);
  EXPECT_TRUE(used);
  PetscOptionsUsed(nullptr, "hs_newton_ksp_type", &used);
  EXPECT_FALSE(used);
  for (const char* name : {"-hs_control_ksp_type", "-ksp_max_it", "-hs_newton_ksp_type"})
    PetscOptionsClearValue(nullptr, name);
}

}  // namespace mpi_test_control
}  // namespace
