// The distributed problem as a whole, on 1 and 2 ranks: the assembled tangent is the
// derivative of the assembled residual (finite differences through ghosts, Dirichlet rows,
// follower pressure and gravity together), the matrix is preallocated exactly (insertion
// outside the pattern is an error) and carries the six rigid-body modes, the plain Newton's
// options take the command line over the deck over the preset, and boundary entries that
// prescribe one node differently are refused before any solve.
#include <gtest/gtest.h>
#include <petscsnes.h>

#include <filesystem>
#include <random>
#include <stdexcept>
#include <utility>

#include "../materials/material_fixtures.hpp"
#include "../tangent_check.hpp"
#include "common/deck_reader.hpp"
#include "common/error.hpp"
#include "deck/boundary_conflicts.hpp"
#include "deck/deck.hpp"
#include "mesh/distribution.hpp"
#include "mesh/mesh_h5.hpp"
#include "mesh/rigid_motions.hpp"
#include "run_deck.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/multi_solve.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/problem.hpp"
#include "solvers/solver_options.hpp"

namespace {
namespace mpi_test_problem {

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

using hs_test::check_tangent;
using hs_test::TangentCheck;

class TangentTest : public ::testing::TestWithParam<std::tuple<int, std::string>> {};

TEST_P(TangentTest, TangentIsDerivativeOfResidual) {
  const auto [order, model] = GetParam();
  Fixture f({"mesh.order=" + std::to_string(order), "materials[0].density=1000",
             "loads.pressure[0].value=2e5"});
  // The deck's small-strain constants (E = 1e6, nu = 0.3) in each law (material_fixtures.hpp).
  auto& material = f.config.materials[0];
  material.law = hs::material_fixtures::make_law(model, material.law->elastic_constants());
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  const hs::VecHandle u(problem.create_vector()), v(problem.create_vector());
  // Strains of a few percent; at 0.02 a point of the order-2 mesh on 2 ranks passed Gent's
  // limiting chain (I1b - 3 >= Jm = 10), where the law is not defined.
  fill_random(u, 0.01, 1);
  fill_random(v, 1.0, 2);
  const double s = 0.7;
  problem.apply_dirichlet(u, s);
  problem.apply_dirichlet(v, 0.0);  // directions that keep the constraints
  const hs::MatHandle J(problem.create_matrix());
  ASSERT_TRUE(problem.jacobian(u, s, J));
  const TangentCheck c = check_tangent(problem, J, u, v, s);
  ASSERT_GE(c.error, 0) << "a residual failed";
  EXPECT_LT(c.error, 1e-6 * c.size) << "order " << order << " " << model;
  EXPECT_GT(c.size, 0);

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
}

INSTANTIATE_TEST_SUITE_P(
    Models, TangentTest,
    ::testing::Combine(::testing::Values(1, 2),
                       ::testing::ValuesIn(hs::material_fixtures::finite_strain_law_names())));

// The nodal-pressure element of P1 meshes (solvers/nodal_pressure.hpp) on 1 and 2 ranks: its
// tangent, whose patch coupling reaches across the rank boundary, is the derivative of its
// residual, and its residual the derivative of its energy, for every law with a (ln J)^2
// volumetric term, at nu = 0.49 (kappa/mu = 50).
class NodalPressureTest : public ::testing::TestWithParam<std::string> {};

// Volume multipliers of an incompressible body (solvers/nodal_pressure.hpp) as a solve
// leaves them: any values, the same on every rank for a node (from its global index).
// Patches' multipliers by node id, then F-bar elements' by element id.
void set_volume_multipliers(hs::Problem& problem, const hs::Distribution& dist, double scale) {
  ASSERT_TRUE(problem.has_volume_multipliers());
  std::vector<double> lambda = problem.volume_multipliers();
  const size_t nodal = problem.has_nodal_volume_multipliers() ? dist.num_local() : 0;
  for (size_t k = 0; k < lambda.size(); ++k) {
    const int64_t id = k < nodal ? dist.local_nodes[k] : dist.local_tets[k - nodal];
    lambda[k] = scale * (static_cast<double>((id * 7919) % 1000) / 1000 - 0.3);
  }
  problem.set_volume_multipliers(lambda);
}

// The residual is the gradient of the energy and the tangent its Hessian, at nu 0.49 and at
// nu = 0.5 with volume multipliers of the order of the shear modulus.
void check_derivatives(const std::string& law, double nu) {
  Fixture f({"mesh.order=1", "materials[0].density=1000"});
  f.config.pressures.clear();  // a potential: the energy check below
  auto& material = f.config.materials[0];
  material.law = hs::material_fixtures::make_law(law, hs::elastic_constants_from_E_nu(1e6, nu));
  material.element = hs::ElementFormulation::nodal_pressure;
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  if (nu == 0.5) set_volume_multipliers(problem, f.dist, 3e5);
  const hs::VecHandle u(problem.create_vector()), v(problem.create_vector());
  fill_random(u, 0.01, 5);
  fill_random(v, 1.0, 6);
  const double s = 0.7;
  problem.apply_dirichlet(u, s);
  problem.apply_dirichlet(v, 0.0);
  const hs::MatHandle J(problem.create_matrix());
  ASSERT_TRUE(problem.jacobian(u, s, J));
  const TangentCheck c = check_tangent(problem, J, u, v, s);
  ASSERT_GE(c.error, 0) << "a residual failed";
  const PetscReal ref = c.size;
  EXPECT_LT(c.error, 1e-6 * ref) << law;
  EXPECT_GT(ref, 0);

  hs::VecHandle R, up, um;
  for (auto* h : {&R, &up, &um}) VecDuplicate(u, h->out());
  const double eps = 1e-6;
  VecWAXPY(up, eps, v, u);
  VecWAXPY(um, -eps, v, u);

  ASSERT_TRUE(problem.residual(u, s, R));
  PetscScalar slope = 0;
  VecDot(R, v, &slope);
  double Ep = 0, Em = 0;
  ASSERT_TRUE(problem.potential_energy(up, s, &Ep));
  ASSERT_TRUE(problem.potential_energy(um, s, &Em));
  EXPECT_NEAR((Ep - Em) / (2 * eps), slope, 1e-6 * std::abs(slope)) << law;

  // The tangent is symmetric (the element has an energy) and wider than the displacement
  // element's: a node couples to its neighbours' neighbours.
  PetscBool symmetric = PETSC_FALSE;
  MatIsSymmetric(J, 1e-10 * ref, &symmetric);
  EXPECT_TRUE(symmetric);
  material.element = hs::ElementFormulation::displacement;
  hs::Problem plain(f.config, f.dist, PETSC_COMM_WORLD);
  const hs::MatHandle J0(plain.create_matrix());
  MatInfo wide, narrow;
  MatGetInfo(J, MAT_GLOBAL_SUM, &wide);
  MatGetInfo(J0, MAT_GLOBAL_SUM, &narrow);
  EXPECT_GT(wide.nz_used, 1.5 * narrow.nz_used);
}

TEST_P(NodalPressureTest, TangentAndResidualAreDerivatives) { check_derivatives(GetParam(), 0.49); }

TEST_P(NodalPressureTest, WithVolumeMultipliersTangentAndResidualAreDerivatives) {
  check_derivatives(GetParam(), 0.5);
}

// The pressure patch test: a homogeneous deformation u = A X on the distorted mesh of the
// thick sphere gives every patch the same volume ratio, so the nodal pressures are all the
// law's, k ln J / J (small strains: lambda tr A), no pressure mode is excited, and every
// interior node is in equilibrium to round-off (the symmetry planes carry no shear: A is
// diagonal).
TEST_P(NodalPressureTest, HomogeneousDeformationIsReproducedExactly) {
  Fixture f({"mesh.order=1"});
  f.config.pressures.clear();
  f.config.gravity = {0, 0, 0};
  auto& material = f.config.materials[0];
  material.law =
      hs::material_fixtures::make_law(GetParam(), hs::elastic_constants_from_E_nu(1e6, 0.4999));
  material.element = hs::ElementFormulation::nodal_pressure;
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  const hs::VecHandle u(problem.create_vector()), R(problem.create_vector());
  const double A[3] = {0.02, -0.01, 0.015};
  PetscScalar* a;
  VecGetArray(u, &a);
  for (int64_t n = 0; n < f.dist.num_owned(); ++n)
    for (int d = 0; d < 3; ++d) a[3 * n + d] = A[d] * problem.reference_coordinate(n, d);
  VecRestoreArray(u, &a);
  ASSERT_TRUE(problem.residual(u, 1.0, R));
  const double k = material.law->volumetric_modulus();
  const double J = (1 + A[0]) * (1 + A[1]) * (1 + A[2]);
  const double p = material.law->small_strain() ? k * (A[0] + A[1] + A[2]) : k * std::log(J) / J;
  const std::vector<double> pressure = problem.nodal_pressure(u);
  ASSERT_EQ(static_cast<int64_t>(pressure.size()), f.dist.num_owned());
  double worst_pressure = 0, worst_force = 0, largest_force = 0;
  const PetscScalar* r;
  VecGetArrayRead(R, &r);
  for (int64_t n = 0; n < f.dist.num_owned(); ++n) {
    worst_pressure = std::max(worst_pressure, std::abs(pressure[n] + p));
    double radius = 0;
    for (int d = 0; d < 3; ++d) radius += std::pow(problem.reference_coordinate(n, d), 2);
    radius = std::sqrt(radius);
    const bool interior = radius > 1.0 + 1e-9 && radius < 2.0 - 1e-9;
    for (int d = 0; d < 3; ++d) {
      if (problem.constrained(3 * n + d)) continue;
      largest_force = std::max(largest_force, std::abs(r[3 * n + d]));
      if (interior) worst_force = std::max(worst_force, std::abs(r[3 * n + d]));
    }
  }
  VecRestoreArrayRead(R, &r);
  EXPECT_LT(worst_pressure, 1e-9 * std::abs(p)) << GetParam();
  EXPECT_LT(worst_force, 1e-9 * largest_force) << GetParam();
  EXPECT_GT(largest_force, 0);
}

// Newton's tangent (Problem::jacobian) takes the volumetric pressures linearised from the
// previous tangent's point, per patch of a nodal-pressure body (solvers/nodal_pressure.hpp),
// per element of an F-bar body (fem/element.hpp): from the same point it is the exact
// tangent, and from a point eps away it differs from it by O(eps^2) (the linearisation of
// ln J is right to first order): halving eps divides the difference by 4. After
// exact_next_tangent() it is the exact tangent from any point.
// With `incompressible`, nu = 0.5 and volume multipliers in the pressures.
void check_newton_tangent(const std::string& law_name, hs::ElementFormulation element,
                          bool incompressible = false) {
  Fixture f({element == hs::ElementFormulation::fbar ? "mesh.order=2" : "mesh.order=1"});
  f.config.pressures.clear();
  auto& material = f.config.materials[0];
  material.law = hs::material_fixtures::make_law(
      law_name, hs::elastic_constants_from_E_nu(1e6, incompressible ? 0.5 : 0.4999));
  material.element = element;
  const auto& law = *material.law;
  hs::Problem exact(f.config, f.dist, PETSC_COMM_WORLD);
  if (incompressible) set_volume_multipliers(exact, f.dist, 3e5);
  const hs::VecHandle u(exact.create_vector()), v(exact.create_vector()), u0(exact.create_vector());
  fill_random(u, 0.01, 7);
  fill_random(v, 0.01, 8);
  exact.apply_dirichlet(u, 1.0);
  exact.apply_dirichlet(v, 0.0);
  const hs::MatHandle K(exact.create_matrix());
  ASSERT_TRUE(exact.jacobian(u, 1.0, K));
  PetscReal size = 0;
  MatNorm(K, NORM_FROBENIUS, &size);
  auto difference = [&](double eps, bool forget) {
    hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
    if (incompressible) set_volume_multipliers(problem, f.dist, 3e5);
    const hs::MatHandle J(problem.create_matrix());
    VecWAXPY(u0, -eps, v, u);
    EXPECT_TRUE(problem.jacobian(u0, 1.0, J));
    if (forget) problem.exact_next_tangent();
    EXPECT_TRUE(problem.jacobian(u, 1.0, J));
    MatAXPY(J, -1.0, K, SAME_NONZERO_PATTERN);
    PetscReal d = 0;
    MatNorm(J, NORM_FROBENIUS, &d);
    return d;
  };
  EXPECT_LT(difference(0.0, false), 1e-14 * size) << law.name();
  EXPECT_LT(difference(1.0, true), 1e-14 * size) << law.name();
  if (law.small_strain()) {
    EXPECT_LT(difference(1.0, false), 1e-14 * size);  // linear: no history
    return;
  }
  const double d1 = difference(1.0, false), d2 = difference(0.5, false);
  EXPECT_GT(d1, 1e-10 * size) << law.name();  // it does differ away from the point
  EXPECT_NEAR(d1 / d2, 4.0, 0.4) << law.name();
}

TEST_P(NodalPressureTest, TangentFromThePreviousPointIsRightToSecondOrder) {
  check_newton_tangent(GetParam(), hs::ElementFormulation::nodal_pressure);
}

TEST_P(NodalPressureTest, WithVolumeMultipliersTangentFromThePreviousPointIsRightToSecondOrder) {
  check_newton_tangent(GetParam(), hs::ElementFormulation::nodal_pressure, true);
}

class FbarNewtonTest : public ::testing::TestWithParam<std::string> {};

TEST_P(FbarNewtonTest, TangentFromThePreviousPointIsRightToSecondOrder) {
  check_newton_tangent(GetParam(), hs::ElementFormulation::fbar);
}

TEST_P(FbarNewtonTest, WithVolumeMultipliersTangentFromThePreviousPointIsRightToSecondOrder) {
  check_newton_tangent(GetParam(), hs::ElementFormulation::fbar, true);
}

INSTANTIATE_TEST_SUITE_P(Laws, FbarNewtonTest,
                         ::testing::Values("neo_hookean", "mooney_rivlin", "yeoh", "gent"));

INSTANTIATE_TEST_SUITE_P(Laws, NodalPressureTest,
                         ::testing::Values("neo_hookean", "mooney_rivlin", "yeoh", "gent",
                                           "linear_elastic"));

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
  const hs::VecHandle u(problem.create_vector()), v(problem.create_vector()),
      R(problem.create_vector());
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
  const auto reference = hs_test::run_deck("cantilever_gravity.yaml", deck, "roundoff_ref");
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
  EXPECT_THROW(hs_test::run_deck("cantilever_gravity.yaml", unreachable, "roundoff_off"),
               hs::SolveError);
}

// An evaluation that meets inverted elements names one, the same on every rank; the next
// evaluation without any clears it (an earlier trial step must not be blamed later).
TEST(InvertedElement, NamedOnEveryRankAndClearedByTheNextEvaluation) {
  Fixture f({"materials[0].model=neo_hookean"});  // linear elasticity never inverts
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  const hs::VecHandle u(problem.create_vector()), R(problem.create_vector());
  const hs::MatHandle J(problem.create_matrix());
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
}

// Several right-hand sides through one factorization at once give what one solve each gives,
// with a direct solver (MatMatSolve) and with an iterative one (a solve per column).
class SolveColumns : public ::testing::TestWithParam<std::string> {};

TEST_P(SolveColumns, EqualOneSolveEach) {
  Fixture f({"materials[0].model=neo_hookean"});
  hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
  const hs::VecHandle u(problem.create_vector());
  fill_random(u, 0.01, 7);
  problem.apply_dirichlet(u, 1.0);
  const hs::MatHandle J(problem.create_matrix());
  ASSERT_TRUE(problem.jacobian(u, 1.0, J));
  hs::KspHandle ksp;
  KSPCreate(PETSC_COMM_WORLD, ksp.out());
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
  std::vector<hs::VecHandle> owned;  // b's, x's and y's
  std::vector<Vec> b(3), x(3), y(3);
  for (int j = 0; j < 3; ++j) {
    for (Vec* w : {&b[j], &x[j], &y[j]}) *w = owned.emplace_back(problem.create_vector());
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
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, SolveColumns, ::testing::Values("mumps", "gamg"));

TEST(SolverOptions, UnknownTypesAreRefusedBeforeAnyWork) {
  hs::SolverConfig solver;
  solver.petsc_options = {{"ksp_type", "nonsense"}};
  try {
    hs::check_solver_options(solver, "deck.yaml");
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
  EXPECT_NO_THROW(hs::check_solver_options(solver, "deck.yaml"));
  PetscOptionsSetValue(nullptr, "-pc_type", "no_such_pc");  // as if on the command line
  solver.petsc_options.clear();
  try {
    hs::check_solver_options(solver, "deck.yaml");
    FAIL() << "-pc_type no_such_pc was accepted";
  } catch (const hs::InputError& e) {
    EXPECT_STREQ(e.what(), "command line: -pc_type: unknown PETSc type 'no_such_pc'");
  }
  PetscOptionsClear(nullptr);
  // With an object's prefix: on the command line and in the deck.
  PetscOptionsSetValue(nullptr, "-hs_bordered_ksp_type", "no_such_ksp");
  try {
    hs::check_solver_options(solver, "deck.yaml");
    FAIL() << "-hs_bordered_ksp_type no_such_ksp was accepted";
  } catch (const hs::InputError& e) {
    EXPECT_STREQ(e.what(), "command line: -hs_bordered_ksp_type: unknown PETSc type 'no_such_ksp'");
  }
  PetscOptionsClear(nullptr);
  solver.petsc_options = {{"hs_control_pc_type", "nonsense"}};
  try {
    hs::check_solver_options(solver, "deck.yaml");
    FAIL() << "hs_control_pc_type nonsense was accepted";
  } catch (const hs::InputError& e) {
    EXPECT_STREQ(
        e.what(),
        "deck.yaml: solver.petsc_options.hs_control_pc_type: unknown PETSc type 'nonsense'");
  }
}

// A misspelt prefix was read by no object, without a word: -hs_bordred_ksp_type preonly ran the
// bordered Newton with its preset's solver.
TEST(SolverOptions, UnknownPrefixesAreRefusedBeforeAnyWork) {
  hs::SolverConfig solver;
  const std::string known = "the solver objects' prefixes are " + [] {
    std::vector<std::string> prefixes(std::begin(hs::kSolverPrefixes),
                                      std::end(hs::kSolverPrefixes));
    return hs::join(prefixes);
  }() + "; docs/decks.md, \"Solver options\")";
  solver.petsc_options = {{"hs_bordred_ksp_type", "preonly"}};
  try {
    hs::check_solver_options(solver, "deck.yaml");
    FAIL() << "hs_bordred_ksp_type was accepted";
  } catch (const hs::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "deck.yaml: solver.petsc_options.hs_bordred_ksp_type: unknown hydrosoft option "
              "prefix (did you mean hs_bordered_ksp_type? " +
                  known);
  }
  solver.petsc_options.clear();
  PetscOptionsSetValue(nullptr, "-hs_contrl_correction_ksp_rtol", "1e-3");  // the command line
  try {
    hs::check_solver_options(solver, "deck.yaml");
    FAIL() << "-hs_contrl_correction_ksp_rtol was accepted";
  } catch (const hs::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "command line: -hs_contrl_correction_ksp_rtol: unknown hydrosoft option prefix "
              "(did you mean -hs_control_correction_ksp_rtol? " +
                  known);
  }
  PetscOptionsClear(nullptr);
  // Each object's prefix, one letter dropped, is taken back to it; spelt right, it passes.
  for (const char* prefix : hs::kSolverPrefixes) {
    const std::string right = std::string(prefix) + "ksp_rtol";
    const std::string wrong = right.substr(0, 4) + right.substr(5);
    solver.petsc_options = {{wrong, "1e-3"}};
    try {
      hs::check_solver_options(solver, "deck.yaml");
      ADD_FAILURE() << wrong << " was accepted";
    } catch (const hs::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("(did you mean " + right + "?"), std::string::npos)
          << e.what();
    }
    solver.petsc_options = {{right, "1e-3"}};
    EXPECT_NO_THROW(hs::check_solver_options(solver, "deck.yaml")) << right;
  }
  // hydrosoft's unprefixed options, and PETSc's own (which PETSc reports if unused), pass.
  solver.petsc_options = {{"hs_near_null_space", "false"},
                          {"hs_newton_monitor", ""},
                          {"ksp_rtol", "1e-6"},
                          {"mat_mumps_icntl_14", "50"}};
  EXPECT_NO_THROW(hs::check_solver_options(solver, "deck.yaml"));
  solver.petsc_options = {{"hs_near_nul_space", "false"}};
  EXPECT_THROW(hs::check_solver_options(solver, "deck.yaml"), hs::InputError);
  // The partitioner's type is checked as the solvers' are.
  solver.petsc_options = {{"hs_partition_mat_partitioning_type", "ptscotch"}};
  EXPECT_NO_THROW(hs::check_solver_options(solver, "deck.yaml"));
  solver.petsc_options = {{"mat_partitioning_type", "no_such_partitioner"}};
  EXPECT_THROW(hs::check_solver_options(solver, "deck.yaml"), hs::InputError);
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

// The unit block (meshes/block.geo, h = 0.5) clamped at its bottom, its face x = 0 moved by
// 0.03 m along x: the 3 nodes of the edge they share take two values of x. Before, the later
// entry won there and step 2 of a neo-Hookean block halved its increment without end. Read
// from the .geo (on rank 0, then distributed) and from an .h5 (read in parts by every rank,
// so that a node's groups come from other ranks): the same message on 1 and 2 ranks.
TEST(BoundaryConflicts, TwoValuesOfOneNodeAreRefusedNamingBothEntries) {
  const std::string conditions = "boundary=[{group: bottom}, {group: x0, value: [0.03, 0, 0]}]";
  const std::string message =
      "hydrostatic_patch.yaml: boundary[1]: group 'x0' prescribes x = 0.03 m on 3 nodes that "
      "boundary[0] (group 'bottom') prescribes x = 0 m (one at (0, 0, 0)); a component of a "
      "node takes one condition: give both the same value, or leave the shared nodes out of one "
      "of the groups";
  const std::vector<std::string> block = {"mesh.order=1", "exact={type: none}", "time.steps=2",
                                          "materials[0].model=neo_hookean", conditions};
  auto refused = [&](const std::vector<std::string>& overrides, const std::string& tag) {
    try {
      hs_test::run_deck("hydrostatic_patch.yaml", overrides, tag);
      return std::string("run");
    } catch (const hs::InputError& e) {
      EXPECT_FALSE(std::filesystem::exists(hs_test::out_folder(tag))) << tag;
      return std::string(e.what());
    }
  };
  std::string m = refused(block, "geo");
  EXPECT_NE(m.find(message), std::string::npos) << m;

  const std::string h5 = hs_test::out_folder("block.h5");
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  const hs::Config config =
      hs::parse_deck(kSource + "/input/hydrostatic_patch.yaml", {"mesh.order=1"});
  const auto mesh = hs::load_mesh_on_rank_zero(config.mesh, PETSC_COMM_WORLD);
  if (rank == 0) hs::write_mesh_h5(*mesh, h5);
  MPI_Barrier(PETSC_COMM_WORLD);
  std::vector<std::string> from_h5 = block;
  from_h5[0] = "mesh={file: " + h5 + "}";
  m = refused(from_h5, "h5");
  EXPECT_NE(m.find(message), std::string::npos) << m;

  // A symmetry plane (x only) meeting a face moved along x; the y and z of the shared nodes
  // are the moved face's alone, and agreeing entries (the same value, 0 ramped or not, an
  // exact solution on every face) pass.
  std::vector<std::string> plane = block;
  plane.back() = "boundary=[{group: x0, components: [x]}, {group: bottom, value: [0.01, 0, 0]}]";
  m = refused(plane, "plane");
  EXPECT_NE(m.find("boundary[1]: group 'bottom' prescribes x = 0.01 m on 3 nodes that "
                   "boundary[0] (group 'x0') prescribes x = 0 m (one at (0, 0, 0))"),
            std::string::npos)
      << m;
}

// The corners of the unit cube, by hand: which pairs of entries conflict, and the message's
// count, components and first node (the smallest coordinates).
TEST(BoundaryConflicts, WhatConflictsAndWhatAgrees) {
  const std::vector<double> x = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0,
                                 0, 0, 1, 1, 0, 1, 0, 1, 1, 1, 1, 1};
  const std::map<std::string, std::vector<int32_t>> groups = {
      {"bottom", {0, 1, 2, 3}}, {"x0", {0, 2, 4, 6}}, {"x1", {1, 3, 5, 7}}};
  auto bc = [](const std::string& group, std::array<double, 3> value, bool scaled = true,
               std::array<bool, 3> components = {true, true, true}) {
    hs::DirichletConfig c;
    c.group = group;
    c.value = value;
    c.scaled = scaled;
    c.components = components;
    return c;
  };
  // Radial from the origin: 0 along x on the plane x = 0, as a symmetry plane there.
  const hs::ExactValue radial = [](const std::array<double, 3>& X, double s) {
    return std::array<double, 3>{0.1 * s * X[0], 0.1 * s * X[1], 0.1 * s * X[2]};
  };
  auto check = [&](std::vector<hs::DirichletConfig> conditions) {
    hs::Config config;
    config.deck_path = "deck.yaml";
    config.dirichlet = std::move(conditions);
    try {
      hs::check_boundary_conflicts(config, groups, x, 8, radial, MPI_COMM_SELF);
      return std::string();
    } catch (const hs::InputError& e) {
      return std::string(e.what());
    }
  };
  EXPECT_EQ(check({bc("bottom", {0, 0, 0}), bc("x0", {0, 0, 0})}), "");
  EXPECT_EQ(check({bc("bottom", {0, 0, 0}, false), bc("x0", {0, 0, 0})}), "");
  EXPECT_EQ(check({bc("bottom", {0, 0, 0}), bc("x0", {0, 0, 0.2}, true, {true, true, false})}), "");
  EXPECT_EQ(check({bc("x0", {0, 0, 0}, true, {true, false, false}), bc("x1", {0.5, 0, 0})}), "");
  hs::DirichletConfig exact = bc("bottom", {0, 0, 0}, true, {true, true, false});
  exact.exact = true;
  EXPECT_EQ(check({bc("x0", {0, 0, 0}, true, {true, false, false}), exact}), "");
  EXPECT_EQ(check({bc("bottom", {0, 0, 0}), bc("x0", {0, 0.2, 0.1}), bc("x1", {0, 0, 0.1})}),
            "deck.yaml: boundary[1]: group 'x0' prescribes y = 0.2 m, z = 0.1 m on 2 nodes that "
            "boundary[0] (group 'bottom') prescribes y = 0 m, z = 0 m (one at (0, 0, 0)); a "
            "component of a node takes one condition: give both the same value, or leave the "
            "shared nodes out of one of the groups");
  EXPECT_NE(check({bc("bottom", {0.1, 0, 0}, false), bc("x1", {0.1, 0, 0})})
                .find("group 'x1' prescribes x = 0.1 m on 2 nodes that boundary[0] (group "
                      "'bottom') prescribes x = 0.1 m at once (scaled: false) (one at (1, 0, 0))"),
            std::string::npos);
  EXPECT_NE(check({exact, bc("x1", {0, 0, 0}, true, {true, false, false})})
                .find("group 'x1' prescribes x = 0 m on 2 nodes that boundary[0] (group "
                      "'bottom') prescribes x from the exact solution (one at (1, 0, 0))"),
            std::string::npos);
  // The later of three: x1 agrees with bottom, x0 does not.
  EXPECT_NE(check({bc("bottom", {0, 0, 0}), bc("x1", {0, 0, 0}), bc("x0", {0, 0, 1})})
                .find("boundary[2]: group 'x0' prescribes z = 1 m on 2 nodes that boundary[0]"),
            std::string::npos);
}

// The plain Newton's options (prefix hs_newton_): the command line's prefixed option over its
// unprefixed one over the deck over the preset, down to GAMG's level smoothers, which PETSc
// makes when the SNES first solves; nothing of the preset or the deck in the global database.
TEST(SolverOptions, CommandLineWinsOverDeckOverPreset) {
  PetscOptionsSetValue(nullptr, "-ksp_type", "bcgs");  // as if given on the command line
  PetscOptionsSetValue(nullptr, "-ksp_max_it", "300");
  PetscOptionsSetValue(nullptr, "-hs_newton_ksp_max_it", "400");
  Fixture f({"materials[0].model=neo_hookean", "solver.preset=gamg"});
  f.config.solver.petsc_options = {{"ksp_type", "cg"},
                                   {"ksp_rtol", "1e-9"},
                                   {"pc_gamg_threshold", "0.05"},
                                   {"mg_levels_ksp_type", "richardson"},
                                   {"mg_levels_pc_type", "sor"}};
  {
    hs::Problem problem(f.config, f.dist, PETSC_COMM_WORLD);
    hs::NewtonSolver newton(problem, f.config.solver, hs::TangentKind{});
    const hs::VecHandle u(problem.create_vector());
    problem.apply_dirichlet(u, 0.1);
    newton.solve(u, 0.1);
    KSP ksp;
    SNESGetKSP(newton.snes(), &ksp);
    KSPType type;
    KSPGetType(ksp, &type);
    EXPECT_STREQ(type, "bcgs");
    PetscReal rtol = 0, snes_rtol = 0;
    PetscInt max_it = 0;
    KSPGetTolerances(ksp, &rtol, nullptr, nullptr, &max_it);
    EXPECT_DOUBLE_EQ(rtol, 1e-9);
    EXPECT_EQ(max_it, 400);
    SNESGetTolerances(newton.snes(), nullptr, &snes_rtol, nullptr, nullptr, nullptr);
    EXPECT_DOUBLE_EQ(snes_rtol, 1e-8);  // the preset's
    PC pc;
    KSPGetPC(ksp, &pc);
    PCType pc_type;
    PCGetType(pc, &pc_type);
    EXPECT_STREQ(pc_type, "gamg");
    PetscInt levels = 0;
    PCMGGetLevels(pc, &levels);
    ASSERT_GT(levels, 1);
    KSP smoother;
    PCMGGetSmoother(pc, levels - 1, &smoother);
    KSPGetType(smoother, &type);
    EXPECT_STREQ(type, "richardson");
  }
  for (const char* name : {"-pc_type", "-snes_rtol", "-ksp_rtol", "-pc_gamg_threshold",
                           "-mg_levels_ksp_type", "-snes_linesearch_type"}) {
    PetscBool set = PETSC_TRUE;
    PetscOptionsHasName(nullptr, nullptr, name, &set);
    EXPECT_FALSE(set) << name;
  }
  char value[64];
  PetscBool set;
  PetscOptionsGetString(nullptr, nullptr, "-ksp_type", value, sizeof value, &set);
  EXPECT_STREQ(value, "bcgs");
  PetscOptionsClear(nullptr);
}

// A handle releases its object once, when it goes, on an exception too, and not after it
// was moved from; out() releases what it held. Seen through PETSc's reference count: an
// extra reference taken here shows each release as one count less.
PetscInt references(Vec v) {
  PetscInt n = 0;
  PetscObjectGetReference(reinterpret_cast<PetscObject>(v), &n);
  return n;
}

TEST(PetscHandle, ReleasesOnceOnEveryWayOut) {
  hs::VecHandle kept;
  VecCreateSeq(PETSC_COMM_SELF, 3, kept.out());
  const Vec v = kept;
  PetscObjectReference(reinterpret_cast<PetscObject>(v));  // the handles below own this one
  ASSERT_EQ(references(v), 2);
  {
    hs::VecHandle first(v);
    hs::VecHandle second(std::move(first));
    EXPECT_EQ(first.get(), nullptr);
    EXPECT_EQ(references(v), 2);  // moving releases nothing
  }
  EXPECT_EQ(references(v), 1);  // released once, by the handle it was moved to
  PetscObjectReference(reinterpret_cast<PetscObject>(v));
  try {
    hs::VecHandle owner(v);
    throw std::runtime_error("a failed step");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(references(v), 1);
  PetscObjectReference(reinterpret_cast<PetscObject>(v));
  hs::VecHandle reused(v);
  VecDuplicate(v, reused.out());  // releases v's reference before it writes the new vector
  EXPECT_EQ(references(v), 1);
  EXPECT_NE(reused.get(), v);
  EXPECT_EQ(references(reused), 1);
}

}  // namespace mpi_test_problem
}  // namespace
