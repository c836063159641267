// Self-contact (docs/contact.md, "Self-contact") on 1 and 2 ranks: two linear elastic blocks
// of one mesh (meshes/two_blocks.geo, their facing surfaces meshed apart), the upper pressed
// down onto the lower across a gap, take the uniaxial force of their compression, which the
// clamp of the lower balances; the surfaces never meet; the contact pressure written per node
// is the uniaxial stress; 2 ranks give 1 rank's forces. The
// assembled tangent with pairs acting is the derivative of the assembled residual. The
// shipped PneuNet's chamber walls press on each other, which adds to its bending, and their
// forces, internal, leave the clamp with the weight alone. A deck whose surfaces start within
// the barrier's distance is refused before any work.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "../mpi_test_decks.hpp"
#include "../tangent_check.hpp"
#include "common/error.hpp"
#include "deck/deck.hpp"
#include "solvers/distributed_mesh.hpp"
#include "solvers/problem.hpp"
#include "solvers/simulation.hpp"

namespace {
namespace mpi_test_self_contact {

using Json = nlohmann::json;
const std::string kSource = HYDROSOFT_SOURCE_DIR;

// L = 0.1 m blocks of H = 0.05 m, 1 mm apart, the upper's top moved down by 4 mm, free
// sideways (symmetry planes x0, y0).
std::string blocks_deck(const std::string& contact) {
  return "mesh:\n  file: " + kSource +
         "/meshes/two_blocks.geo\n  order: 1\n"
         "materials:\n"
         "  - {group: body, model: linear_elastic, E: 1.0e5, nu: 0.3}\n"
         "boundary:\n"
         "  - {group: bottom, components: [z]}\n"
         "  - {group: top, components: [z], value: [0, 0, -0.004]}\n"
         "  - {group: x0, components: [x]}\n"
         "  - {group: y0, components: [y]}\n"
         "contact: {surfaces: [lower_top, upper_bottom], self: true" +
         contact +
         "}\n"
         "time: {type: static, steps: 16}\n";
}

Json run(const std::string& deck, const std::string& tag, MPI_Comm comm) {
  const std::string folder = (hs_test::test_folder() / tag).string();
  return hs::run_simulation(hs::parse_deck(deck, {"output.folder=" + folder}), comm);
}

TEST(SelfContact, TwoBlocksPressedTogetherTakeTheUniaxialForceOfTheirCompression) {
  // Uniform uniaxial stress: the two blocks in series shorten by delta - g0 + gap, so the
  // force is E A (delta - g0 + gap) / (2 H) with the gap between 0 and dhat.
  const double E = 1e5, H = 0.05, A = 0.01, delta = 0.004, g0 = 0.001;
  const std::string deck = hs_test::write_deck("blocks.yaml", blocks_deck(""));
  const Json s = hs_test::shared(run(deck, "blocks", MPI_COMM_WORLD));
  const double top = s["reactions_N"]["top"][2], bottom = s["reactions_N"]["bottom"][2];
  const double dhat = s["contact"]["distance_m"];
  const double low = E * A * (delta - g0) / (2 * H), high = E * A * (delta - g0 + dhat) / (2 * H);
  EXPECT_GT(-top, low);
  EXPECT_LT(-top, high);
  EXPECT_NEAR(bottom, -top, 1e-7 * low);  // the contact passes the force on whole
  const Json& self = s["contact"]["self"];
  EXPECT_GT(self["pairs"].get<int>(), 50);
  const double gap = self["min_gap_m"];
  EXPECT_GT(gap, 0);  // the surfaces never meet
  EXPECT_LT(gap, dhat);
  // The pairs' forces add up to the load (their sideways parts, from the triangles' edges
  // and corners, cancel over the surface).
  EXPECT_NEAR(self["force_N"].get<double>(), -top, 0.03 * low);
  // The output's fields: away from the edges the contact pressure is the uniaxial stress
  // F / A on both faces (the median of each face's inner nodes), and the gap field's
  // smallest value is the summary's.
  if (hs_test::world_rank() == 0) {
    const std::string h5 = (hs_test::test_folder() / "blocks" / "blocks.h5").string();
    const std::string last = "/step_" + std::to_string(s["outputs"].get<int>() - 1);
    const std::vector<double> X = hs_test::read_dataset(h5, "/mesh/coordinates");
    const std::vector<double> p = hs_test::read_dataset(h5, last + "/self_contact_pressure");
    const std::vector<double> d = hs_test::read_dataset(h5, last + "/self_contact_gap");
    ASSERT_EQ(X.size(), 3 * p.size());
    for (const double z : {H, H + g0}) {
      std::vector<double> face;
      for (size_t n = 0; n < p.size(); ++n) {
        const double x = X[3 * n], y = X[3 * n + 1];
        if (std::abs(X[3 * n + 2] - z) < 1e-9 && x > 0.005 && x < 0.095 && y > 0.005 && y < 0.095)
          face.push_back(p[n]);
      }
      ASSERT_GT(face.size(), 10u) << z;
      std::nth_element(face.begin(), face.begin() + face.size() / 2, face.end());
      EXPECT_NEAR(face[face.size() / 2], -top / A, 0.03 * -top / A) << z;
    }
    EXPECT_DOUBLE_EQ(*std::min_element(d.begin(), d.end()), gap);
    EXPECT_LE(*std::max_element(d.begin(), d.end()), dhat);
  }
  if (hs_test::world_size() > 1) {
    Json one;
    if (hs_test::world_rank() == 0) one = run(deck, "blocks_one", MPI_COMM_SELF);
    one = hs_test::shared(one);
    EXPECT_NEAR(one["reactions_N"]["top"][2].get<double>(), top, 1e-6 * low);
    EXPECT_EQ(one["contact"]["self"]["pairs"], self["pairs"]);
  }
}

// The tangent against central differences of the residual, with the upper block moved down
// into the barrier's reach (tilted and roughened, so that the pairs meet faces, edges and
// corners and the gaps differ), along a random direction: the pairs' Hessians reach the
// assembled matrix whole, across ranks and through the pattern that grows.
TEST(SelfContact, TheTangentIsTheResidualsDerivativeWhereThePairsAct) {
  const std::string deck = hs_test::write_deck("tangent.yaml", blocks_deck(""));
  const hs::Config config = hs::parse_deck(deck, {});
  const hs::Distribution dist = hs::load_distributed_mesh(config.mesh, PETSC_COMM_WORLD);
  hs::Problem problem(config, dist, PETSC_COMM_WORLD);
  const double H = 0.05, g0 = 0.001, dhat = problem.self_contact()->barrier().distance;
  const hs::VecHandle u(problem.create_vector()), v(problem.create_vector());
  PetscScalar *ua, *va;
  VecGetArray(u, &ua);
  VecGetArray(v, &va);
  for (int64_t n = 0; n < dist.num_owned(); ++n) {
    const double x = problem.reference_coordinate(n, 0), y = problem.reference_coordinate(n, 1),
                 z = problem.reference_coordinate(n, 2);
    // Noise that depends on the node's place only, the same on any number of ranks.
    std::mt19937 random(static_cast<unsigned>(1e6 * (x + 3 * y + 7 * z)));
    std::uniform_real_distribution<double> noise(-1, 1);
    for (int d = 0; d < 3; ++d) {
      ua[3 * n + d] = 0.02 * dhat * noise(random);
      va[3 * n + d] = noise(random);
    }
    if (z > H + 0.5 * g0) ua[3 * n + 2] -= g0 - dhat * (0.4 + 2 * x + 1.5 * y);
  }
  VecRestoreArray(u, &ua);
  VecRestoreArray(v, &va);
  problem.apply_dirichlet(u, 0.0);
  problem.apply_dirichlet(v, 0.0);
  ASSERT_GT(problem.self_contact_totals(u).pairs, 50);
  ASSERT_GT(problem.self_contact_totals(u).min_gap, 0.3 * dhat);
  const hs::MatHandle J(problem.create_matrix());
  ASSERT_TRUE(problem.jacobian(u, 0.0, J));
  const hs_test::TangentCheck c = hs_test::check_tangent(problem, J, u, v, 0.0, 1e-4 * dhat);
  ASSERT_GE(c.error, 0) << "a residual failed";
  EXPECT_LT(c.error, 1e-6 * c.size) << c.error / c.size;
}

// input/pneunet_self_contact.yaml, coarser (h 4 mm): at 24 kPa the chamber walls bulge across
// the slots and press on each other; their pairs' forces are internal, so the clamp holds the
// weight alone, as at rest (and as without contact), to round-off; the walls never meet; and
// their contact pushes the chambers' tops apart: the tip turns further than when the walls
// pass through each other (the same deck without self-contact).
TEST(SelfContact, ThePneuNetsWallsPressOnEachOtherAndBendItFurther) {
  const std::string shipped = kSource + "/input/pneunet_self_contact.yaml";
  const std::vector<std::string> coarse = {"mesh.parameters.h=0.004"};
  auto with = [&](const std::string& tag, const std::string& deck) {
    std::vector<std::string> o = coarse;
    o.push_back("output.folder=" + (hs_test::test_folder() / tag).string());
    return hs_test::shared(hs::run_simulation(hs::parse_deck(deck, o), MPI_COMM_WORLD));
  };
  const Json s = with("pneunet", shipped);
  ASSERT_EQ(s["status"], "ok");
  const Json& self = s["contact"]["self"];
  EXPECT_GT(self["pairs"].get<int>(), 10);
  EXPECT_GT(self["force_N"].get<double>(), 0.5);
  const double dhat = s["contact"]["distance_m"], gap = self["min_gap_m"];
  EXPECT_GT(gap, 0);
  EXPECT_LT(gap, dhat);
  const double weight = s["states"][0]["reactions_N"]["base"][2];
  EXPECT_GT(weight, 0.2);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(s["reactions_N"]["base"][d].get<double>(), d == 2 ? weight : 0.0, 1e-9 * weight);

  std::ifstream in(shipped);
  std::stringstream text;
  text << in.rdbuf();
  std::string free = text.str();
  free.replace(free.find("../meshes/"), 10, kSource + "/meshes/");
  free.erase(free.find("\ncontact:") + 1);  // the deck's last lines: contact, solver
  free += "solver: {preset: mumps}\n";
  const Json f = with("pneunet_free", hs_test::write_deck("pneunet_free.yaml", free));
  ASSERT_EQ(f["status"], "ok");
  const double turned = s["states"].back()["tip"]["rotation_deg"];
  const double passing = f["states"].back()["tip"]["rotation_deg"];
  EXPECT_GT(turned, passing + 2) << turned << " against " << passing;
}

TEST(SelfContact, SurfacesThatStartWithinTheBarriersDistanceAreRefused) {
  const std::string deck = hs_test::write_deck("near.yaml", blocks_deck(", distance: 0.002"));
  try {
    run(deck, "near", MPI_COMM_WORLD);
    FAIL() << "no error";
  } catch (const hs::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("contact.self"), std::string::npos) << what;
    EXPECT_NE(what.find("0.001 m from a triangle"), std::string::npos) << what;
  }
}

}  // namespace mpi_test_self_contact
}  // namespace
