// Self-contact (docs/contact.md, "Self-contact") on 1 and 2 ranks: two linear elastic blocks
// of one mesh (meshes/two_blocks.geo, their facing surfaces meshed apart), the upper pressed
// down onto the lower across a gap, take the uniaxial force of their compression, which the
// clamp of the lower balances; the surfaces never meet; 2 ranks give 1 rank's forces. A deck
// whose surfaces start within the barrier's distance is refused before any work.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <string>

#include "../mpi_test_decks.hpp"
#include "common/error.hpp"
#include "deck/deck.hpp"
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
  if (hs_test::world_size() > 1) {
    Json one;
    if (hs_test::world_rank() == 0) one = run(deck, "blocks_one", MPI_COMM_SELF);
    one = hs_test::shared(one);
    EXPECT_NEAR(one["reactions_N"]["top"][2].get<double>(), top, 1e-6 * low);
    EXPECT_EQ(one["contact"]["self"]["pairs"], self["pairs"]);
  }
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
