// The verification decks, run whole (mesh, assembly, Newton, output) on 1 and 2 ranks:
// errors against the closed-form solutions, and the 2-rank answer against a 1-rank run of
// the same deck made inside the same test (on MPI_COMM_SELF of rank 0).
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "../mpi_test_folder.hpp"
#include "deck/deck.hpp"
#include "solvers/simulation.hpp"

namespace {
namespace mpi_test_verification {

const std::string kSource = HYDROSOFT_SOURCE_DIR;

int world_size() {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

// Inside the test's own folder, removed when the test ends.
std::string out_folder(const std::string& name) { return (hs_test::test_folder() / name).string(); }

nlohmann::json run(const std::string& deck, std::vector<std::string> overrides,
                   MPI_Comm comm = MPI_COMM_WORLD, const std::string& tag = "") {
  overrides.push_back("output.folder=" +
                      out_folder(std::filesystem::path(deck).stem().string() + tag));
  const hs::Config config = hs::parse_deck(kSource + "/input/" + deck, overrides);
  return hs::run_simulation(config, comm);
}

// Runs the deck on the world communicator and, when there are several ranks, once more on
// rank 0 alone; the two must agree to solver tolerance.
double l2_error_checked_against_one_rank(const std::string& deck,
                                         const std::vector<std::string>& o) {
  const auto world = run(deck, o);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  double l2 = world.contains("error") ? world["error"]["l2_relative"].get<double>() : 0.0;
  MPI_Bcast(&l2, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  if (world_size() > 1 && rank == 0) {
    const auto single = run(deck, o, MPI_COMM_SELF, "_self");
    EXPECT_NEAR(single["error"]["l2_relative"].get<double>(), l2, 1e-9 * l2 + 1e-14);
    EXPECT_EQ(single["dofs"], world["dofs"]);
  }
  return l2;
}

TEST(Verification, LameSphereP1Converges) {
  // Halving h must cut the P1 error by about 4 (rate 2); coarse levels show rate ~1.7.
  const double coarse =
      l2_error_checked_against_one_rank("lame_sphere.yaml", {"mesh.parameters.h=0.4"});
  const double fine =
      l2_error_checked_against_one_rank("lame_sphere.yaml", {"mesh.parameters.h=0.2"});
  EXPECT_LT(fine, 0.08);
  EXPECT_GT(coarse / fine, 2.8);
  EXPECT_LT(coarse / fine, 5.0);
}

TEST(Verification, LameSphereP2IsMoreAccurate) {
  const double e1 =
      l2_error_checked_against_one_rank("lame_sphere.yaml", {"mesh.parameters.h=0.4"});
  const double e2 = l2_error_checked_against_one_rank("lame_sphere.yaml",
                                                      {"mesh.parameters.h=0.4", "mesh.order=2"});
  EXPECT_LT(e2, e1 / 5);
}

TEST(Verification, HydrostaticPatchP2IsExact) {
  const double e = l2_error_checked_against_one_rank("hydrostatic_patch.yaml", {});
  EXPECT_LT(e, 1e-10);
}

TEST(Verification, CantileverEulerBernoulli) {
  const auto s = run("cantilever_gravity.yaml", {"mesh.parameters.n=3"});
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    // Shear (Timoshenko) adds about 0.8 (1 + nu)(h/L)^2 = 0.26% to the beam value.
    EXPECT_NEAR(s["verification"]["tip_relative_error"].get<double>(), 0.0026, 0.01);
  }
}

}  // namespace mpi_test_verification
}  // namespace

namespace {
namespace mpi_test_verification {

TEST(Verification, ElasticaLargeDeflection) {
  // beta = q L^3 / (E I) = 4: v/L = 0.42516 for the inextensible elastica; the 3D beam
  // (L/h = 20, neo-Hookean, P2) is within 1%.
  const auto s = run("cantilever_gravity.yaml",
                     {"materials[0].E=1.1772e7", "materials[0].model=neo_hookean", "time.steps=8"});
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_EQ(s["verification"]["reference"], "elastica");
    EXPECT_NEAR(s["verification"]["tip_reference"].get<double>(), 0.42516, 1e-4);
    EXPECT_NEAR(s["verification"]["tip_relative_error"].get<double>(), 0.0, 0.01);
  }
}

TEST(Verification, NeoHookeanSpherePastThePressurePeak) {
  // Driven by the inner radius to stretch 2.2, past the peak at 1.8281: the pressure from the
  // reactions follows the closed-form curve at every step, falling after the peak.
  const auto s = run("neo_hookean_sphere.yaml", {});
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) return;
  const auto& steps = s["verification"]["steps"];
  ASSERT_EQ(steps.size(), 12u);
  double peak = 0;
  for (const auto& step : steps) {
    EXPECT_NEAR(step["pressure_relative_error"].get<double>(), 0.0, 0.005) << step.dump();
    peak = std::max(peak, step["pressure_over_mu"].get<double>());
  }
  EXPECT_NEAR(peak, 0.816424, 0.01);
  EXPECT_LT(steps.back()["pressure_over_mu"].get<double>(), peak - 0.01);
}

}  // namespace mpi_test_verification
}  // namespace
