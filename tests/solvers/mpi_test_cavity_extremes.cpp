// Stiff and extreme cavity cases on 1 and 2 ranks (docs/stiff_cases.md, "Cavities"): a
// mercury-filled cylinder converges and its liquid weighs rho g V; a weightless liquid is an
// air cavity; volumes that cannot exist, collapsed cavities and pressures past the pressure
// peak stop with messages that name the deck, the state, the cavity and the reason, and leave
// no output behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "common/error.hpp"
#include "deck/deck.hpp"
#include "mesh/distribution.hpp"
#include "mesh/gmsh_io.hpp"
#include "run_deck.hpp"
#include "solvers/bordered_newton.hpp"
#include "solvers/constraints/constraint_set.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/problem.hpp"
#include "solvers/simulation.hpp"

namespace {
namespace mpi_test_cavity_extremes {

const std::string kSource = HYDROSOFT_SOURCE_DIR;

// Every case here is the coarse compressible cylinder (../mpi_test_decks.hpp).
nlohmann::json run(const std::string& deck, const std::vector<std::string>& overrides,
                   const std::string& tag) {
  return hs_test::run_deck(deck, hs_test::coarse_cylinder(overrides), "cavity_extremes_" + tag);
}

// The message of the error that running the deck throws ("" if it runs), and no output
// folder (nor its staging folder) left behind.
template <typename Error>
std::string error_of(const std::string& deck, const std::vector<std::string>& overrides,
                     const std::string& tag) {
  const std::string folder = hs_test::out_folder("cavity_extremes_" + tag);
  std::string message;
  try {
    run(deck, overrides, tag);
  } catch (const Error& e) {
    message = e.what();
  }
  // Rank 0 removes the staging folder as the error unwinds it: look once it has.
  MPI_Barrier(MPI_COMM_WORLD);
  EXPECT_FALSE(std::filesystem::exists(folder)) << folder;
  EXPECT_FALSE(std::filesystem::exists(folder + ".partial")) << folder;
  return message;
}

std::string g4(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", x);
  return text;
}

TEST(CavityExtremes, MercuryConvergesAndWeighsRhoGV) {
  // 13.6 times water: the cylinder hangs at ~61 deg (water: 17 deg); the increments are cut
  // back but the run finishes.
  const auto s = run("cylinder_water.yaml", {"cavities[0].density=13600"}, "mercury");
  ASSERT_EQ(s["states"].size(), 2u);
  for (int k : {0, 1}) {
    const auto& c = s["states"][k]["cavities"][0];
    const double volume = c["volume"].get<double>(), total = c["fluid_weight_total"].get<double>();
    // Exactly rho g times the column volume, and the column volume is the cavity's volume to
    // the column method's accuracy on a 200^2 grid.
    EXPECT_NEAR(total, 13600 * 9.81 * c["fluid_weight_volume"].get<double>(), 1e-10 * total);
    EXPECT_NEAR(total, 13600 * 9.81 * volume, 2e-3 * total) << "state " << k;
  }
  EXPECT_NEAR(s["states"][0]["cavities"][0]["fluid_weight_total"].get<double>(), 10.39, 0.02);
  EXPECT_NEAR(s["states"][0]["tip"]["inclination_deg"].get<double>(), 60.72, 0.3);
  EXPECT_NEAR(s["states"][1]["tip"]["inclination_deg"].get<double>(), 60.14, 0.3);
  EXPECT_NEAR(s["states"][1]["added_volume_ml"].get<double>(), 15.0, 1e-8);
}

TEST(CavityExtremes, WeightlessLiquidIsAnAirCavity) {
  const std::vector<std::string> steps = {"states[0].steps=2", "states[1].steps=4"};
  auto o = steps;
  o.push_back("cavities[0].density=0");
  const auto liquid = run("cylinder_water.yaml", o, "rho0");
  const auto air = run("cylinder_air.yaml", steps, "air");
  EXPECT_EQ(liquid["parts"]["fluid_weight"]["device"], "none");
  EXPECT_EQ(liquid["parts"]["fluid_weight"]["calls"], 0);
  for (int k : {0, 1}) {
    const auto &a = liquid["states"][k], &b = air["states"][k];
    EXPECT_NEAR(a["tip"]["inclination_deg"].get<double>(),
                b["tip"]["inclination_deg"].get<double>(), 1e-10);
    const double p = b["cavities"][0]["pressure"].get<double>();
    EXPECT_NEAR(a["cavities"][0]["pressure"].get<double>(), p, 1e-10 * std::abs(p) + 1e-12);
    EXPECT_EQ(a["cavities"][0]["fluid_weight_total"].get<double>(), 0.0);
  }
  EXPECT_NEAR(air["states"][1]["cavities"][0]["pressure"].get<double>(), 7916, 30);
}

TEST(CavityExtremes, VolumesThatCannotExistAreRefused) {
  // Withdrawing 200 ml from the 79 ml cavity used to "converge" on walls passed through each
  // other (volume -121 ml); now the target is refused before the state is solved.
  const std::string later = error_of<hs::InputError>(
      "cylinder_air.yaml", {"states[0].steps=1", "states[1].cavities.cavity.added_volume=-2e-4"},
      "later");
  EXPECT_NE(later.find("input/cylinder_air.yaml: state 'inflated': cavity 'cavity': added_volume "
                       "-0.0002 m^3 would leave it a volume of -0.00012"),
            std::string::npos)
      << later;
  EXPECT_NE(later.find("m^3 at the end of the first state); a cavity's volume must stay > 0"),
            std::string::npos)
      << later;
  const std::string first = error_of<hs::InputError>(
      "cylinder_air.yaml", {"cavities[0].added_volume=-2e-4", "states=[{name: rest, steps: 1}]"},
      "first");
  EXPECT_NE(first.find("input/cylinder_air.yaml: cavity 'cavity': added_volume -0.0002 m^3 would "
                       "leave it a volume of -0.0001209 m^3 (it holds 7.908e-05 m^3 undeformed); "
                       "a cavity's volume must stay > 0"),
            std::string::npos)
      << first;
  const std::string density =
      error_of<hs::InputError>("cylinder_water.yaml", {"cavities[0].density=-1000"}, "density");
  EXPECT_NE(density.find("input/cylinder_water.yaml: cavities[0].density: must be >= 0, got -1000"),
            std::string::npos)
      << density;
}

TEST(CavityExtremes, PressurePastThePeakStopsWithItsReason) {
  // The air cylinder's pressure peaks at ~21.4 kPa (near +150 ml); 30 kPa has no equilibrium.
  const std::string m = error_of<hs::SolveError>(
      "cylinder_air.yaml",
      {"states=[{name: rest, steps: 1}, {name: inflated, steps: 1, cavities: {cavity: {pressure: "
       "3e4}}}]",
       "time.max_cutbacks=2"},
      "peak");
  EXPECT_NE(m.find("state 'inflated' at 0.75 of the way: Newton did not converge"),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("; cavity 'cavity' was at 22500 Pa on a pressure ramp (past a pressure peak or "
                   "a buckling of the walls there is no equilibrium under pressure control: "
                   "prescribe added_volume to pass it)"),
            std::string::npos)
      << m;
  EXPECT_EQ(m.find("nan"), std::string::npos) << m;
}

TEST(CavityExtremes, CollapsedCavityIsOutsideTheDomain) {
  // Mirroring the body through the plane y = 0 turns the cavity inside out (V -> -V). Newton
  // refuses to start there and names the cavity instead of an inverted element.
  const hs::Config config =
      hs::parse_deck(kSource + "/input/cylinder_air.yaml", hs_test::coarse_cylinder());
  const hs::Distribution dist = hs::load_distributed_mesh(config.mesh, PETSC_COMM_WORLD);
  hs::Problem problem(config, dist, PETSC_COMM_WORLD);
  hs::ConstraintSet cavities(config, problem);
  hs::BorderedNewton newton(problem, cavities, config.solver, hs::TangentKind{false, true});
  const hs::VecHandle u(problem.create_vector()), R(problem.create_vector());
  PetscScalar* a;
  VecGetArray(u, &a);
  for (int64_t n = 0; n < dist.num_owned(); ++n)
    a[3 * n + 1] = -2 * problem.reference_coordinate(n, 1);
  VecRestoreArray(u, &a);
  std::vector<double> c;
  EXPECT_FALSE(cavities.residual(u, 1.0, R, c));
  const double v0 = cavities[0].reference_measure();
  EXPECT_NEAR(cavities[0].measure(), -v0, 1e-12 * v0);
  const std::string reason = "cavity 'cavity' reaches a volume of " + g4(-v0) +
                             " m^3 <= 0 (its walls pass through each other)";
  EXPECT_EQ(cavities.collapse_reason(), reason);
  const hs::NewtonResult r = newton.solve(u, 1.0);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.reason, reason);
  // At rest the same cavity is inside the domain again.
  VecSet(u, 0.0);
  EXPECT_TRUE(cavities.residual(u, 1.0, R, c));
  EXPECT_EQ(cavities.collapse_reason(), "");
}

}  // namespace mpi_test_cavity_extremes
}  // namespace
