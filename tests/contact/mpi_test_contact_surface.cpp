// A surface obstacle in a run, on 1 and 2 ranks: a box written as 12 triangles (binary STL,
// and OBJ) and brought down into a clamped block gives the analytic box's run: the same
// force on the obstacle, the same clamp reaction and the same displacement at every node;
// two tessellated balls in one file press as two spheres do, within the facets' angles.
// The box's corners are dyadic numbers, exact in the STL's single precision. Newton converges
// to 1e-11 of its first residual or 1e-9 N: the runs' paths differ by round-off (on 2 ranks the
// iterations and cutbacks differ), so only their converged answers are compared.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <string>
#include <vector>

#include "../mpi_test_decks.hpp"
#include "deck/deck.hpp"
#include "solvers/simulation.hpp"
#include "surface_test_util.hpp"

namespace {
namespace mpi_test_contact_surface {

using Json = nlohmann::json;
const std::string kSource = HYDROSOFT_SOURCE_DIR;

struct PressRun {
  Json summary;
  std::vector<double> displacement;  // the last step's, rank 0
};

PressRun press(const std::string& tag, const std::string& obstacle) {
  const std::string folder = (hs_test::test_folder() / tag).string();
  const std::string deck = hs_test::write_deck(
      tag + ".yaml",
      "mesh:\n  file: " + kSource +
          "/meshes/block.geo\n  order: 1\n  parameters: {H: 0.1, h: 0.03}\n"
          "materials:\n"
          "  - {group: body, model: neo_hookean, E: 1.0e5, nu: 0.45}\n"
          "boundary:\n  - {group: bottom}\n"
          "obstacles:\n  - {name: press, " +
          obstacle +
          ", move: [0, 0, -0.008]}\n"
          "contact: {surfaces: [top, sides]}\n"
          "time: {type: static, steps: 8}\n"
          "solver: {petsc_options: {hs_newton_snes_rtol: 1.0e-11, hs_newton_snes_atol: 1.0e-9}}\n");
  PressRun run;
  run.summary = hs_test::shared(
      hs::run_simulation(hs::parse_deck(deck, {"output.folder=" + folder}), MPI_COMM_WORLD));
  if (hs_test::world_rank() == 0)
    run.displacement = hs_test::read_dataset(folder + "/" + tag + ".h5", "/step_7/displacement");
  return run;
}

TEST(SurfaceObstacle, ABoxOfTrianglesPressesAsTheAnalyticBox) {
  const Eigen::Vector3d center(0.05078125, 0.05078125, 0.109375),
      size(0.0390625, 0.0390625, 0.015625);
  const hs_test::Surface box = hs_test::box_surface(center, size);
  const std::string stl = (hs_test::test_folder() / "box.stl").string(),
                    obj = (hs_test::test_folder() / "box.obj").string();
  if (hs_test::world_rank() == 0) {
    hs_test::write_stl_binary(stl, box);
    hs_test::write_obj(obj, box);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  const PressRun analytic = press("analytic",
                                  "type: box, center: [0.05078125, 0.05078125, 0.109375], "
                                  "size: [0.0390625, 0.0390625, 0.015625]");
  const PressRun from_stl = press("stl", "type: surface, file: box.stl");
  const PressRun from_obj = press("obj", "type: surface, file: box.obj");
  const auto& f = analytic.summary["contact"]["obstacles"][0]["force_N"];
  const double scale = std::abs(f[2].get<double>());
  ASSERT_GT(scale, 0.5);  // the box presses
  for (const PressRun* other : {&from_stl, &from_obj}) {
    const Json& s = other->summary;
    for (int d = 0; d < 3; ++d) {
      EXPECT_NEAR(s["contact"]["obstacles"][0]["force_N"][d].get<double>(), f[d].get<double>(),
                  1e-10 * scale);
      EXPECT_NEAR(s["reactions_N"]["bottom"][d].get<double>(),
                  analytic.summary["reactions_N"]["bottom"][d].get<double>(), 1e-10 * scale);
    }
    EXPECT_NEAR(s["contact"]["min_gap_m"].get<double>(),
                analytic.summary["contact"]["min_gap_m"].get<double>(), 1e-14);
    if (hs_test::world_rank() != 0) continue;
    ASSERT_EQ(other->displacement.size(), analytic.displacement.size());
    for (size_t k = 0; k < analytic.displacement.size(); ++k)
      EXPECT_NEAR(other->displacement[k], analytic.displacement[k], 1e-12) << k;  // of 8 mm
  }
}

TEST(SurfaceObstacle, TwoBallsInOneFilePressAsTwoSpheres) {
  // Two tessellated balls in one STL: an obstacle that is not convex (between the balls the
  // tangent of the gap is no bound of it). Brought down 8 mm into the clamped block, it pushes
  // with the clamp's reaction, no node reaches it, and its force is the two analytic
  // spheres' within what the facets change: a node pushed by a facet is pushed along its
  // normal, up to 0.04 rad from the sphere's radius on a 4-times refined icosphere (edges of
  // 0.07 rad), so by up to 4 % of the force sideways (each ball touches few nodes here).
  const double R = 0.018;
  hs_test::Surface two = hs_test::icosphere(4, R);
  const size_t nv = two.vertices.size(), nt = two.triangles.size();
  for (size_t v = 0; v < nv; ++v) two.vertices.push_back(two.vertices[v]);
  for (size_t t = 0; t < nt; ++t) {
    two.triangles.push_back(two.triangles[t]);
    for (int& k : two.triangles.back()) k += static_cast<int>(nv);
  }
  for (size_t v = 0; v < 2 * nv; ++v)
    two.vertices[v] += Eigen::Vector3d(v < nv ? 0.03 : 0.07, 0.05, 0.12);
  const std::string stl = (hs_test::test_folder() / "two_balls.stl").string();
  if (hs_test::world_rank() == 0) hs_test::write_stl_binary(stl, two);
  MPI_Barrier(MPI_COMM_WORLD);
  const PressRun analytic =
      press("two_spheres",
            "type: sphere, center: [0.03, 0.05, 0.12], radius: 0.018, move: [0, 0, -0.008]}\n"
            "  - {name: other, type: sphere, center: [0.07, 0.05, 0.12], radius: 0.018");
  const PressRun mesh = press("two_balls", "type: surface, file: two_balls.stl");
  const auto& f = mesh.summary["contact"]["obstacles"][0]["force_N"];
  const auto& clamp = mesh.summary["reactions_N"]["bottom"];
  const double scale = f[2].get<double>();
  ASSERT_GT(scale, 0.5);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(f[d].get<double>(), clamp[d].get<double>(), 1e-7 * scale) << d;
  EXPECT_GT(mesh.summary["contact"]["min_gap_m"].get<double>(), 0);
  const auto& a = analytic.summary["contact"]["obstacles"];
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(f[d].get<double>(),
                a[0]["force_N"][d].get<double>() + a[1]["force_N"][d].get<double>(), 0.05 * scale)
        << d;
}

}  // namespace mpi_test_contact_surface
}  // namespace
