// The distributed problem as a whole, on 1 and 2 ranks: the assembled tangent is the
// derivative of the assembled residual (finite differences through ghosts, Dirichlet rows,
// follower pressure and gravity together), the matrix is preallocated exactly (insertion
// outside the pattern is an error) and carries the six rigid-body modes, and the solver
// options take the command line over the deck over the preset.
#include <gtest/gtest.h>
#include <petscsnes.h>

#include <random>

#include "common/error.hpp"
#include "deck/deck.hpp"
#include "mesh/distribution.hpp"
#include "mesh/rigid_motions.hpp"
#include "run_deck.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/multi_solve.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/problem.hpp"

namespace {

const std::string kSource = HYDROSOFT_SOURCE_DIR;

struct Fixture {
  hs::Config config;
  hs::Distribution dist;
  explicit Fixture(std::vector<std::string> overrides) {
    overrides.push_back("mesh.parameters.h=0.5");
    config = hs::parse_deck(kSource + "/input/lame_sphere.yaml", overrides);
    config.gravity = {0.3, -9.81, 0.1};
    dist = hs::load_distributed_mesh(config.mesh, PETSC_COMM_WORLD);
  }
};

void fill_random(Vec v, double scale, unsigned seed) {
  PetscInt lo, hi;
  VecGetOwnershipRange(v, &lo, &hi);
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> d(-scale, scale);
  for (PetscInt i = 0; i < hi; ++i) {  // same stream on every rank: values depend on i only
    const double x = d(gen);
    if (i >= lo) VecSetValue(v, i, x, INSERT_VALUES);
  }
  VecAssemblyBegin(v);
  VecAssemblyEnd(v);
}

class TangentTest : public ::testing::TestWithParam<std::tuple<int, std::string>> {};

TEST_P(TangentTest, TangentIsDerivativeOfResidual) {
  const auto [order, model] = GetParam();
  Fixture f({"mesh.order=" + std::to_string(order), "materials[0].model=" + model,
             "materials[0].density=1000", "loads.pressure[0].value=2e5"});
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  Vec u = problem.create_vector(), v = problem.create_vector();
  fill_random(u, 0.02, 1);
  fill_random(v, 1.0, 2);
  const double s = 0.7;
  problem.apply_dirichlet(u, s);
  problem.apply_dirichlet(v, 0.0);  // directions that keep the constraints
  Mat J = problem.create_matrix();
  ASSERT_TRUE(problem.jacobian(u, s, J));
  Vec Jv, Rp, Rm, up, um;
  VecDuplicate(u, &Jv);
  VecDuplicate(u, &Rp);
  VecDuplicate(u, &Rm);
  VecDuplicate(u, &up);
  VecDuplicate(u, &um);
  MatMult(J, v, Jv);
  const double eps = 1e-6;
  VecWAXPY(up, eps, v, u);
  VecWAXPY(um, -eps, v, u);
  ASSERT_TRUE(problem.residual(up, s, Rp));
  ASSERT_TRUE(problem.residual(um, s, Rm));
  VecAXPY(Rp, -1.0, Rm);
  VecScale(Rp, 1.0 / (2 * eps));  // central difference of R along v
  VecAXPY(Rp, -1.0, Jv);
  PetscReal err, ref;
  VecNorm(Rp, NORM_2, &err);
  VecNorm(Jv, NORM_2, &ref);
  EXPECT_LT(err, 1e-6 * ref) << "order " << order << " " << model;
  EXPECT_GT(ref, 0);

  MatNullSpace nns;
  MatGetNearNullSpace(J, &nns);
  ASSERT_NE(nns, nullptr);
  PetscBool has_constant;
  PetscInt n;
  const Vec* vecs;
  MatNullSpaceGetVecs(nns, &has_constant, &n, &vecs);
  EXPECT_EQ(n, 6);
  PetscInt bs;
  MatGetBlockSize(J, &bs);
  EXPECT_EQ(bs, 3);
  for (Vec* w : {&u, &v, &Jv, &Rp, &Rm, &up, &um}) VecDestroy(w);
  MatDestroy(&J);
}

INSTANTIATE_TEST_SUITE_P(Models, TangentTest,
                         ::testing::Combine(::testing::Values(1, 2),
                                            ::testing::Values("neo_hookean", "corotational",
                                                              "mooney_rivlin",
                                                              "saint_venant_kirchhoff")));

// Without follower pressure the residual is the gradient of the potential energy (the line
// search's objective): its central difference along a direction is R . v.
TEST(PotentialEnergy, DerivativeIsTheResidual) {
  Fixture f({"mesh.order=2", "materials[0].model=neo_hookean", "materials[0].density=1000"});
  {
    hs::Problem with_pressure(f.config, f.dist, PETSC_COMM_WORLD);
    EXPECT_FALSE(with_pressure.has_potential());
  }
  f.config.pressures.clear();
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  ASSERT_TRUE(problem.has_potential());
  Vec u = problem.create_vector(), v = problem.create_vector(), R = problem.create_vector();
  fill_random(u, 0.02, 3);
  fill_random(v, 1.0, 4);
  const double s = 0.8;
  problem.apply_dirichlet(u, s);
  problem.apply_dirichlet(v, 0.0);
  ASSERT_TRUE(problem.residual(u, s, R));
  PetscScalar slope = 0;
  VecDot(R, v, &slope);
  const double eps = 1e-6;
  double Ep = 0, Em = 0;
  VecAXPY(u, eps, v);
  ASSERT_TRUE(problem.potential_energy(u, s, &Ep));
  VecAXPY(u, -2 * eps, v);
  ASSERT_TRUE(problem.potential_energy(u, s, &Em));
  EXPECT_NEAR((Ep - Em) / (2 * eps), slope, 1e-6 * std::abs(slope));
  EXPECT_GT(std::abs(slope), 0);
  // An inverted configuration has no energy, and says so.
  VecScale(v, 10.0);
  VecAXPY(u, 1.0, v);
  double E = 12345;
  EXPECT_FALSE(problem.potential_energy(u, s, &E));
  EXPECT_EQ(E, 12345);
  for (Vec* w : {&u, &v, &R}) VecDestroy(w);
}

// Newton takes full steps by default: the neo-Hookean cantilever of 0.1 x 0.01 x 0.01 m
// (E 1 MPa, nu 0.45) under its own weight, v/L = 0.15, in one load step converges in as many
// iterations as the physics needs (6 here; the line search "cp" took 47 and a cutback), to
// the elastica's tip deflection within the beam model's shear and mesh error, with either
// preset.
class FullNewtonSteps : public ::testing::TestWithParam<std::string> {};

TEST_P(FullNewtonSteps, NeoHookeanCantileverInOneLoadStep) {
  const auto summary = hs_test::run_deck(
      "cantilever_gravity.yaml",
      {"materials[0].model=neo_hookean", "materials[0].E=1e6", "materials[0].nu=0.45",
       "materials[0].density=1070", "mesh.parameters.L=0.1", "mesh.parameters.h=0.01",
       "exact.parameters.L=0.1", "exact.parameters.h=0.01", "solver.preset=" + GetParam()},
      "full_newton_" + GetParam());
  EXPECT_LE(summary["newton_iterations"].get<int>(), 7);
  EXPECT_EQ(summary["cutbacks"].get<int>(), 0);
  EXPECT_NEAR(summary["verification"]["tip_relative_error"].get<double>(), 0.0, 0.03);
  EXPECT_GT(summary["verification"]["tip_deflection"].get<double>(), 0.014);
}

INSTANTIATE_TEST_SUITE_P(Solvers, FullNewtonSteps, ::testing::Values("mumps", "gamg"));

// Tolerances below what floating point can reach (the 10M-dof cantilever's residual stalls
// at 3e-8 of its load, above snes_rtol 1e-8): Newton stops where the residual is within the
// round-off of its own evaluation, at the solution the reachable tolerances give; PETSc's
// test alone iterates on the noise until snes_max_it.
TEST(NewtonRoundoff, UnreachableTolerancesStopAtTheResidualsRoundoff) {
  const std::vector<std::string> deck = {
      "materials[0].model=neo_hookean", "materials[0].E=1e6",      "materials[0].nu=0.45",
      "materials[0].density=1070",      "mesh.parameters.L=0.1",   "mesh.parameters.h=0.01",
      "exact.parameters.L=0.1",         "exact.parameters.h=0.01", "solver.preset=mumps"};
  // Each run starts from an empty options database: a run's defaults stay in it, and a
  // later deck's options do not replace them.
  PetscOptionsClear(nullptr);
  const auto reference = hs_test::run_deck("cantilever_gravity.yaml", deck, "roundoff_ref");
  PetscOptionsClear(nullptr);
  auto unreachable = deck;
  unreachable.push_back("solver.petsc_options.snes_rtol=1e-20");
  unreachable.push_back("solver.petsc_options.snes_atol=1e-30");
  const auto summary = hs_test::run_deck("cantilever_gravity.yaml", unreachable, "roundoff");
  EXPECT_LE(summary["newton_iterations"].get<int>(), reference["newton_iterations"].get<int>() + 2);
  EXPECT_EQ(summary["cutbacks"].get<int>(), 0);
  const double tip = reference["verification"]["tip_deflection"].get<double>();
  EXPECT_NEAR(summary["verification"]["tip_deflection"].get<double>(), tip, 1e-9 * tip);

  unreachable.push_back("solver.petsc_options.hs_newton_roundoff=false");
  unreachable.push_back("solver.petsc_options.snes_max_it=12");
  unreachable.push_back("time.max_cutbacks=0");
  PetscOptionsClear(nullptr);
  EXPECT_THROW(hs_test::run_deck("cantilever_gravity.yaml", unreachable, "roundoff_off"),
               hs::SolveError);
  PetscOptionsClear(nullptr);
}

// An evaluation that meets inverted elements names one, the same on every rank; the next
// evaluation without any clears it (an earlier trial step must not be blamed later).
TEST(InvertedElement, NamedOnEveryRankAndClearedByTheNextEvaluation) {
  Fixture f({"materials[0].model=neo_hookean"});  // linear elasticity never inverts
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  Vec u = problem.create_vector(), R = problem.create_vector();
  Mat J = problem.create_matrix();
  const auto agreed = [&](int64_t e) {
    long long lo = e, hi = e;
    MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_LONG_LONG, MPI_MIN, PETSC_COMM_WORLD);
    MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_LONG_LONG, MPI_MAX, PETSC_COMM_WORLD);
    return lo == hi;
  };
  fill_random(u, 5.0, 3);  // ten times the element size: many elements turn inside out
  EXPECT_FALSE(problem.residual(u, 1.0, R));
  EXPECT_GE(problem.inverted_element(), 0);
  EXPECT_LT(problem.inverted_element(), f.dist.num_global_tets);
  EXPECT_TRUE(agreed(problem.inverted_element()));
  fill_random(u, 1e-4, 4);
  EXPECT_TRUE(problem.residual(u, 1.0, R));
  EXPECT_EQ(problem.inverted_element(), -1);
  fill_random(u, 5.0, 5);
  EXPECT_FALSE(problem.jacobian(u, 1.0, J));
  EXPECT_GE(problem.inverted_element(), 0);
  EXPECT_TRUE(agreed(problem.inverted_element()));
  fill_random(u, 1e-4, 6);
  EXPECT_TRUE(problem.jacobian(u, 1.0, J));
  EXPECT_EQ(problem.inverted_element(), -1);
  MatDestroy(&J);
  VecDestroy(&u);
  VecDestroy(&R);
}

// Several right-hand sides through one factorization at once give what one solve each gives,
// with a direct solver (MatMatSolve) and with an iterative one (a solve per column).
class SolveColumns : public ::testing::TestWithParam<std::string> {};

TEST_P(SolveColumns, EqualOneSolveEach) {
  Fixture f({"materials[0].model=neo_hookean"});
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  Vec u = problem.create_vector();
  fill_random(u, 0.01, 7);
  problem.apply_dirichlet(u, 1.0);
  Mat J = problem.create_matrix();
  ASSERT_TRUE(problem.jacobian(u, 1.0, J));
  KSP ksp;
  KSPCreate(PETSC_COMM_WORLD, &ksp);
  KSPSetOperators(ksp, J, J);
  PC pc;
  KSPGetPC(ksp, &pc);
  if (GetParam() == "mumps") {
    KSPSetType(ksp, KSPPREONLY);
    PCSetType(pc, PCCHOLESKY);
    PCFactorSetMatSolverType(pc, MATSOLVERMUMPS);
  } else {
    KSPSetType(ksp, KSPCG);
    PCSetType(pc, PCGAMG);
    KSPSetTolerances(ksp, 1e-12, PETSC_DEFAULT, PETSC_DEFAULT, 1000);
  }
  std::vector<Vec> b(3), x(3), y(3);
  for (int j = 0; j < 3; ++j) {
    b[j] = problem.create_vector();
    x[j] = problem.create_vector();
    y[j] = problem.create_vector();
    fill_random(b[j], 1.0, 10 + j);
    problem.zero_constrained(b[j]);
  }
  int iterations = 0;
  ASSERT_TRUE(hs::solve_columns(ksp, b, x, &iterations));
  EXPECT_EQ(iterations > 0, GetParam() != "mumps");
  for (int j = 0; j < 3; ++j) {
    KSPSolve(ksp, b[j], y[j]);
    PetscReal ny = 0, nd = 0;
    VecNorm(y[j], NORM_2, &ny);
    VecAXPY(y[j], -1.0, x[j]);
    VecNorm(y[j], NORM_2, &nd);
    EXPECT_LT(nd, 1e-9 * ny) << "column " << j;
    EXPECT_GT(ny, 0.0);
    VecDestroy(&b[j]);
    VecDestroy(&x[j]);
    VecDestroy(&y[j]);
  }
  KSPDestroy(&ksp);
  MatDestroy(&J);
  VecDestroy(&u);
}

INSTANTIATE_TEST_SUITE_P(Solvers, SolveColumns, ::testing::Values("mumps", "gamg"));

TEST(SolverOptions, UnknownTypesAreRefusedBeforeAnyWork) {
  hs::SolverConfig solver;
  solver.petsc_options = {{"ksp_type", "nonsense"}};
  try {
    hs::check_solver_types(solver, "deck.yaml");
    FAIL() << "ksp_type nonsense was accepted";
  } catch (const hs::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "deck.yaml: solver.petsc_options.ksp_type: unknown PETSc type 'nonsense'");
  }
  solver.petsc_options = {{"ksp_type", "cg"},
                          {"pc_type", "gamg"},
                          {"snes_linesearch_type", "bt"},
                          {"mg_levels_ksp_type", "chebyshev"},
                          {"ksp_rtol", "1e-6"}};
  EXPECT_NO_THROW(hs::check_solver_types(solver, "deck.yaml"));
  PetscOptionsSetValue(nullptr, "-pc_type", "no_such_pc");  // as if on the command line
  solver.petsc_options.clear();
  try {
    hs::check_solver_types(solver, "deck.yaml");
    FAIL() << "-pc_type no_such_pc was accepted";
  } catch (const hs::InputError& e) {
    EXPECT_STREQ(e.what(), "command line: -pc_type: unknown PETSc type 'no_such_pc'");
  }
  PetscOptionsClear(nullptr);
}

// A law defined at every strain gives a linear solution even where it turns elements inside
// out (E = 1e-12 under gravity: J down to -1e54 was written as a result); the run now stops
// as a finite-strain one does, naming the element.
TEST(LinearLaw, SolutionThatInvertsAnElementIsRefused) {
  try {
    hs_test::run_deck("cantilever_gravity.yaml", {"materials[0].E=1e-12"}, "linear_inverted");
    FAIL() << "an inverted linear solution was written";
  } catch (const hs::SolveError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("the solution inverts an element"), std::string::npos) << m;
    EXPECT_NE(m.find("is inverted (det F <= 0)"), std::string::npos) << m;
  }
}

TEST(FreeBody, AStaticRunWithoutBoundaryConditionsIsRefusedAtOnce) {
  try {
    hs_test::run_deck("cantilever_gravity.yaml", {"boundary=[]"}, "free_body");
    FAIL() << "a free body was run";
  } catch (const hs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("boundary: nothing holds the body"), std::string::npos)
        << e.what();
  }
}

// The Lame sphere octant held by its three symmetry planes, one of them deleted: the body may
// slide along z (the fault of a fuzzed deck, which Newton met as 8 failed cutbacks).
TEST(FreeBody, ConditionsThatLeaveARigidMotionFreeAreRefusedNamingIt) {
  try {
    hs_test::run_deck("lame_sphere.yaml",
                      {"mesh.parameters.h=0.5",
                       "boundary=[{group: symmetry_x, components: [x]}, "
                       "{group: symmetry_y, components: [y]}]"},
                      "sliding");
    FAIL() << "a body free to slide was run";
  } catch (const hs::InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("boundary: the conditions leave the body free to move (translation along "
                     "z)"),
              std::string::npos)
        << m;
  }
}

// The corners of the unit cube, held in ways whose free motions are known by hand.
TEST(FreeBody, FreeRigidMotionsOfTheUnitCube) {
  const std::vector<double> x = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0,
                                 0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1};
  const std::map<std::string, std::vector<int32_t>> groups = {
      {"bottom", {0, 1, 2, 3}}, {"axis", {0, 4}}, {"corner", {0}}, {"x_edge", {0, 1}}};
  auto free = [&](const std::string& group, std::array<bool, 3> components) {
    hs::DirichletConfig bc;
    bc.group = group;
    bc.components = components;
    auto f = hs::free_rigid_motions<int32_t>({bc}, groups, x, PETSC_COMM_WORLD);
    std::sort(f.begin(), f.end());
    return f;
  };
  using V = std::vector<std::string>;
  EXPECT_EQ(free("bottom", {true, true, true}), V{});
  EXPECT_EQ(free("bottom", {false, false, true}),
            (V{"rotation about z", "translation along x", "translation along y"}));
  EXPECT_EQ(free("axis", {true, true, true}), V{"rotation about z"});
  EXPECT_EQ(free("x_edge", {true, true, true}), V{"rotation about x"});
  EXPECT_EQ(free("corner", {true, true, true}).size(), 3u);  // the three rotations
  EXPECT_EQ(free("corner", {false, false, false}).size(), 6u);
}

TEST(SolverOptions, CommandLineWinsOverDeckOverPreset) {
  PetscOptionsSetValue(nullptr, "-ksp_type", "bcgs");  // as if given on the command line
  hs::SolverConfig solver;
  solver.preset = hs::SolverPreset::gamg;
  solver.petsc_options = {{"ksp_type", "cg"}, {"pc_gamg_threshold", "0.05"}};
  hs::set_solver_options(solver, true);
  char value[64];
  PetscBool set;
  PetscOptionsGetString(nullptr, nullptr, "-ksp_type", value, sizeof value, &set);
  EXPECT_STREQ(value, "bcgs");
  PetscOptionsGetString(nullptr, nullptr, "-pc_gamg_threshold", value, sizeof value, &set);
  EXPECT_STREQ(value, "0.05");
  PetscOptionsGetString(nullptr, nullptr, "-pc_type", value, sizeof value, &set);
  EXPECT_STREQ(value, "gamg");
  PetscOptionsClear(nullptr);
}

}  // namespace
