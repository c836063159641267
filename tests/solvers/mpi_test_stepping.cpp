// Time and load stepping: Newmark conserves the total energy of a linear elastic body under
// a dead load (a conservation law the scheme must satisfy to round-off); backward Euler
// dissipates it; a quasi-static schedule that unloads ends on the exact solution of its
// last load factor. The cutback of a load step always ends, whatever its solves do. The
// tangent predictor of a prescribed boundary motion is a linear body's exact solution and
// second-order on a finite-strain one.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "common/error.hpp"
#include "control_scene.hpp"
#include "deck/deck.hpp"
#include "run_deck.hpp"
#include "solvers/newton_solver.hpp"
#include "solvers/simulation.hpp"
#include "solvers/stepping.hpp"
#include "solvers/stepping/static_stepper.hpp"

namespace {
namespace mpi_test_stepping {

const std::string kSource = HYDROSOFT_SOURCE_DIR;

nlohmann::json run(const std::string& deck, const std::vector<std::string>& overrides,
                   const std::string& tag, MPI_Comm comm = MPI_COMM_WORLD) {
  return hs_test::run_deck(deck, overrides, "stepping_" + tag, comm);
}

// 20 steps of 0.1 s, 0.8 of the first mode's period (the deck resolves it in 2 ms steps): the
// trapezoidal rule conserves the energy whatever the step, and backward Euler's dissipation,
// which grows with it, shows within them.
const std::vector<std::string> kCoarseSteps = {"time.dt=0.1", "time.end_time=2.0"};

TEST(Stepping, NewmarkConservesEnergy) {
  const auto s = run("cantilever_dynamic.yaml", kCoarseSteps, "newmark");
  const double scale = s["energy"]["max_stored"].get<double>();
  EXPECT_GT(scale, 0.05);  // the beam really swung
  EXPECT_LT(s["energy"]["max_drift"].get<double>(), 1e-7 * scale);
  EXPECT_EQ(s["steps"].get<int>(), 20);
}

TEST(Stepping, BackwardEulerDissipatesEnergy) {
  const auto s =
      run("cantilever_dynamic.yaml",
          {"time.dt=0.1", "time.end_time=2.0", "time.integrator=backward_euler"}, "euler");
  const double scale = s["energy"]["max_stored"].get<double>();
  EXPECT_LT(s["energy"]["final"].get<double>(), -0.2 * scale);
}

TEST(Stepping, QuasiStaticScheduleUnloads) {
  const auto s =
      run("bimaterial_bar.yaml",
          {"time.type=quasi_static", "time.steps=2", "time.schedule=[1.0, 0.25]"}, "schedule");
  EXPECT_EQ(s["steps"].get<int>(), 2);
  EXPECT_LT(s["error"]["l2_relative"].get<double>(), 1e-8);
}

// The unit block (input/stretched_block.yaml's mesh: x0, y0 and the bottom held normally) with
// its top face moved up by `lift` at full load, no load else.
std::vector<std::string> lifted_block(double lift, const std::string& material) {
  return {
      "boundary=[{group: x0, components: [x]}, {group: y0, components: [y]}, "
      "{group: bottom, components: [z]}, {group: top, components: [z], value: [0, 0, " +
          std::to_string(lift) + "]}]",
      "loads={}", "exact={type: none}", material};
}

// |R| of the equations at s, at u.
double residual_norm(hs::Problem& problem, Vec u, double s) {
  const hs::VecHandle R(problem.create_vector());
  EXPECT_TRUE(problem.residual(u, s, R));
  PetscReal norm = 0;
  VecNorm(R, NORM_2, &norm);
  return norm;
}

// Uniaxial stress of a linear elastic block: the prediction from rest is the solution, u =
// (-nu e x, -nu e y, e z), which P1 elements represent exactly.
TEST(TangentPredictor, IsTheSolutionOfALinearBody) {
  const double e = 0.01, nu = 0.3;
  hs_test::DeckProblem f("stretched_block.yaml",
                         lifted_block(e,
                                      "materials=[{group: body, model: linear_elastic, "
                                      "E: 1.0e6, nu: 0.3, density: 0}]"));
  hs::Problem& problem = *f.problem;
  hs::NewtonSolver newton(problem, f.config.solver, hs::TangentKind{});
  const hs::VecHandle u(problem.create_vector());
  ASSERT_TRUE(hs::predict_by_tangent(problem, newton, u, 0.0, 1.0));
  const hs::Distribution& dist = problem.distribution();
  const PetscScalar* a;
  VecGetArrayRead(u, &a);
  double largest = 0;
  for (int64_t n = 0; n < dist.num_owned(); ++n) {
    const double* X = &dist.x[3 * n];
    const double exact[3] = {-nu * e * X[0], -nu * e * X[1], e * X[2]};
    for (int d = 0; d < 3; ++d) largest = std::max(largest, std::abs(a[3 * n + d] - exact[d]));
  }
  VecRestoreArrayRead(u, &a);
  MPI_Allreduce(MPI_IN_PLACE, &largest, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  EXPECT_LT(largest, 1e-9 * e);
  // Nothing to predict where the boundary stays.
  EXPECT_FALSE(hs::predict_by_tangent(problem, newton, u, 1.0, 1.0));
}

// A neo-Hookean block at nu 0.4999 on P2 (F-bar) stretched from rest: the prediction's
// residual is second order in the increment, and far below the residual of the boundary's
// jump alone (what the first Newton step started from before).
TEST(TangentPredictor, IsSecondOrderOnANearlyIncompressibleBody) {
  std::vector<std::string> overrides = lifted_block(0.4, "materials[0].nu=0.4999");
  overrides.push_back("mesh.order=2");
  hs_test::DeckProblem f("stretched_block.yaml", overrides);
  hs::Problem& problem = *f.problem;
  hs::NewtonSolver newton(problem, f.config.solver, hs::TangentKind{});
  double predicted[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const double s = 0.1 / (1 << k);
    const hs::VecHandle u(problem.create_vector()), jumped(problem.create_vector());
    problem.apply_dirichlet(jumped, s);
    ASSERT_TRUE(hs::predict_by_tangent(problem, newton, u, 0.0, s));
    predicted[k] = residual_norm(problem, u, s);
    EXPECT_LT(predicted[k], 1e-2 * residual_norm(problem, jumped, s)) << s;
  }
  EXPECT_NEAR(predicted[0] / predicted[1], 4.0, 1.0);
}

// A step whose solve converges within `radius` of the last converged parameter, the radius
// multiplied by `shrink` after each success: advance_with_cutback from 0 to 1 with it. The
// solves are counted, and more than 100,000 of them is a failure (a cutback without end).
struct CutbackRun {
  int solves = 0, successes = 0;
  std::string why;  // what give_up was told; empty if the step reached its end
  double last = 0;  // the last converged parameter
};

CutbackRun cut_back(double from, double to, int max_cutbacks, double radius, double shrink,
                    int64_t max_steps = 0) {
  CutbackRun run;
  run.last = from;
  hs::SteppingStats stats;
  stats.max_steps = max_steps;
  auto attempt = [&](double t) {
    if (++run.solves > 100000) throw std::runtime_error("100000 solves: the cutback does not end");
    hs::NewtonResult r;
    r.iterations = 1;
    r.converged = std::abs(t - run.last) <= radius;
    r.reason = r.converged ? "CONVERGED_FNORM_ABS" : "DIVERGED_MAX_IT";
    if (r.converged) {
      run.last = t;
      ++run.successes;
      radius *= shrink;
    }
    return r;
  };
  try {
    hs::advance_with_cutback(
        from, to, max_cutbacks, stats, MPI_COMM_WORLD, attempt,
        [](double, const hs::NewtonResult&, const std::string& why) { throw hs::SolveError(why); });
  } catch (const hs::SolveError& e) {
    run.why = e.what();
  }
  EXPECT_EQ(stats.steps, run.successes);
  EXPECT_EQ(stats.cutbacks, run.solves - run.successes);
  return run;
}

// The sub-steps converge ever closer to where the step sticks (the reachable distance a
// quarter of the last each time): the increment halves without end. Before, the count of
// halvings started again after each converged sub-step, the parameter stopped changing, and
// the solve at that same value converged again and again.
TEST(Cutback, AnIncrementBelowTheLeastAStepTakesEndsTheStep) {
  const CutbackRun run = cut_back(0, 1, 1000, 0.01, 0.25);
  EXPECT_NE(run.why.find("Newton did not converge (DIVERGED_MAX_IT"), std::string::npos) << run.why;
  EXPECT_NE(run.why.find("a smaller one is below the least a step takes (2^-40 of it)"),
            std::string::npos)
      << run.why;
  EXPECT_LT(run.solves, 200);
  EXPECT_LT(run.last, 0.02);
}

// A step of a few units in the last place of its parameter: the increment stops changing it
// after a few halvings, long before 2^-40 or the deck's 1000 halvings in a row.
TEST(Cutback, AnIncrementThatNoLongerChangesTheParameterEndsTheStep) {
  const CutbackRun run = cut_back(1, 1 + 1e-14, 1000, 0, 1);
  EXPECT_NE(run.why.find("halving the increment again would leave 1 unchanged in floating point"),
            std::string::npos)
      << run.why;
  EXPECT_LE(run.solves, 8);  // 1e-14 is 45 units in the last place of 1
  EXPECT_EQ(run.successes, 0);
}

// Each sub-step converges at 1/1000 of the step and the doubled increment after it fails:
// two solves per sub-step, one of them a cutback, never 10 in a row. 80 cutbacks end it.
TEST(Cutback, TheCutbacksOfOneStepAreBounded) {
  const CutbackRun run = cut_back(0, 1, 10, 1e-3, 1);
  EXPECT_NE(run.why.find("the step was cut back 80 times, the most a step may (8 x "
                         "time.max_cutbacks)"),
            std::string::npos)
      << run.why;
  EXPECT_EQ(run.solves - run.successes, 81);
  // The same step with no bound hit ends at 1.
  const CutbackRun easy = cut_back(0, 1, 10, 0.3, 1);
  EXPECT_EQ(easy.why, "");
  EXPECT_EQ(easy.last, 1);
}

TEST(Cutback, TheSubStepsOfARunAreBounded) {
  const CutbackRun run = cut_back(0, 1, 8, 1.0 / 64, 1, 10);
  EXPECT_NE(run.why.find("the run has taken 10 converged sub-steps, the most it may (16 per "
                         "planned step, at least 256)"),
            std::string::npos)
      << run.why;
  EXPECT_EQ(run.successes, 10);
  EXPECT_EQ(hs::max_substeps(1), 256);
  EXPECT_EQ(hs::max_substeps(100), 1600);
}

}  // namespace mpi_test_stepping
}  // namespace
