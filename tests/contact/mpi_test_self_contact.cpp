// Self-contact (docs/contact.md, "Self-contact") on 1 and 2 ranks: two linear elastic blocks
// of one mesh (meshes/two_blocks.geo, their facing surfaces meshed apart), the upper pressed
// down onto the lower across a gap, take the uniaxial force of their compression, which the
// clamp of the lower balances; the surfaces never meet; the contact pressure written per node
// is the uniaxial stress; 2 ranks give 1 rank's forces. The
// assembled tangent with pairs acting is the derivative of the assembled residual. The
// shipped PneuNet's chamber walls press on each other, which adds to its bending, and their
// forces, internal, leave the clamp with the weight alone. Dragged blocks stick or slide on
// each other as their Coulomb friction allows, and a gripper's friction lifts a block off its
// table. The force one surface exerts on another and its rows are checked, and the controller
// grasps that block with the forces asked. Two sharp edges crossed and pressed together hold
// each other by their edge pair. A deck whose surfaces start within the barrier's distance is
// refused before any work.
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
std::string blocks_deck(const std::string& contact, int order = 1, int steps = 16) {
  return "mesh:\n  file: " + kSource + "/meshes/two_blocks.geo\n  order: " + std::to_string(order) +
         "\n"
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
         "time: {type: static, steps: " +
         std::to_string(steps) + "}\n";
}

Json run(const std::string& deck, const std::string& tag, MPI_Comm comm) {
  const std::string folder = (hs_test::test_folder() / tag).string();
  return hs::run_simulation(hs::parse_deck(deck, {"output.folder=" + folder}), comm);
}

// Uniform uniaxial stress: the two blocks in series shorten by delta - g0 + gap, so the force
// is E A (delta - g0 + gap) / (2 H) with the gap between 0 and dhat.
void check_blocks_pressed_together(int order) {
  const double E = 1e5, H = 0.05, A = 0.01, delta = 0.004, g0 = 0.001;
  const std::string tag = order == 1 ? "blocks" : "blocks_p2";
  const std::string deck =
      hs_test::write_deck(tag + ".yaml", blocks_deck("", order, order == 1 ? 16 : 8));
  const Json s = hs_test::shared(run(deck, tag, MPI_COMM_WORLD));
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
    const std::string h5 = (hs_test::test_folder() / tag / (tag + ".h5")).string();
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
    if (hs_test::world_rank() == 0) one = run(deck, tag + "_one", MPI_COMM_SELF);
    one = hs_test::shared(one);
    EXPECT_NEAR(one["reactions_N"]["top"][2].get<double>(), top, 1e-6 * low);
    EXPECT_EQ(one["contact"]["self"]["pairs"], self["pairs"]);
  }
}

TEST(SelfContact, TwoBlocksPressedTogetherTakeTheUniaxialForceOfTheirCompression) {
  check_blocks_pressed_together(1);
}

// P2: each face's four flat sub-triangles carry the pairs, its edge nodes too.
TEST(SelfContact, TwoP2BlocksPressedTogetherTakeTheUniaxialForceOfTheirCompression) {
  check_blocks_pressed_together(2);
}

// The upper block clamped at its top, brought down onto the lower (clamped at its bottom) and
// dragged 2 mm along x at once (nu = 0: no sideways swelling), with friction mu between the
// facing surfaces.
std::string dragged_blocks(const std::string& mu) {
  return "mesh:\n  file: " + kSource +
         "/meshes/two_blocks.geo\n  order: 1\n"
         "materials:\n"
         "  - {group: body, model: linear_elastic, E: 1.0e5, nu: 0.0}\n"
         "boundary:\n"
         "  - {group: bottom}\n"
         "  - {group: top, value: [0.002, 0, -0.004]}\n"
         "contact: {surfaces: [lower_top, upper_bottom], self: true, friction: " +
         mu +
         "}\n"
         "time: {type: static, steps: 8}\n";
}

// The facing surfaces' relative shift along x per output step: the mean x displacement of the
// upper block's bottom nodes less the lower block's top nodes' (rank 0).
std::vector<double> surface_shift(const std::string& h5, size_t steps) {
  const double H = 0.05, g0 = 0.001;
  const std::vector<double> X = hs_test::read_dataset(h5, "/mesh/coordinates");
  std::vector<double> shift;
  for (size_t k = 0; k < steps; ++k) {
    const auto u = hs_test::read_dataset(h5, "/step_" + std::to_string(k) + "/displacement");
    double sum[2] = {0, 0};
    int count[2] = {0, 0};
    for (size_t n = 0; 3 * n < X.size(); ++n)
      for (int side = 0; side < 2; ++side)
        if (std::abs(X[3 * n + 2] - (side ? H + g0 : H)) < 1e-9) {
          sum[side] += u[3 * n];
          ++count[side];
        }
    shift.push_back(sum[1] / count[1] - sum[0] / count[0]);
  }
  return shift;
}

// Coulomb friction between the blocks: with mu = 1 the blocks' shear under the drag stays
// below mu N and the facing surfaces stick where they touched (their relative shift moves by
// less than the slip eps_v); with mu = 0.1 they slide, and each step's friction is mu times the
// normal force of the step before (lagged), its sideways reaction at the clamp within the
// barrier's own sideways part (under 2 % of the normal force, the pressed surfaces tilting) of
// it. The clamps balance; the friction traction written per node drags the lower block's face
// along +x and the upper's back; 2 ranks give 1 rank's forces; a coefficient given for the
// pair of faces replaces the surfaces' default.
TEST(SelfContact, DraggedBlocksStickWithMuOneAndSlideWithMuATenth) {
  double slid = 0;  // the sideways force with mu 0.1
  for (const std::string mu : {"1.0", "0.1"}) {
    const std::string tag = "drag_" + mu, folder = (hs_test::test_folder() / tag).string();
    const std::string deck = hs_test::write_deck(tag + ".yaml", dragged_blocks(mu));
    const Json s = hs_test::shared(run(deck, tag, MPI_COMM_WORLD));
    ASSERT_EQ(s["status"], "ok");
    const double m = std::stod(mu), eps_v = 0.1 * s["contact"]["distance_m"].get<double>();
    const double fx = s["reactions_N"]["top"][0], fz = -s["reactions_N"]["top"][2].get<double>();
    EXPECT_NEAR(s["reactions_N"]["bottom"][0].get<double>(), -fx, 1e-7 * fz) << mu;
    EXPECT_GT(fx, 0.5) << mu;
    if (mu == "0.1") slid = fx;
    if (hs_test::world_size() > 1) {
      Json one;
      if (hs_test::world_rank() == 0) one = run(deck, tag + "_one", MPI_COMM_SELF);
      one = hs_test::shared(one);
      EXPECT_NEAR(one["reactions_N"]["top"][0].get<double>(), fx, 1e-6 * fz) << mu;
    }
    if (hs_test::world_rank() != 0) continue;
    const auto h = hs_test::read_history(folder);
    const auto& x = h.at("reaction_top_x_N");
    const auto& z = h.at("reaction_top_z_N");
    const auto& normal = h.at("self_contact_force_N");
    const auto& friction = h.at("self_contact_friction_N");
    ASSERT_EQ(x.size(), 8u);
    ASSERT_GT(normal[1], 0) << "touches in the second step";
    const std::vector<double> shift = surface_shift(folder + "/" + tag + ".h5", x.size());
    if (m == 1.0) {
      for (size_t k = 2; k < x.size(); ++k) {
        EXPECT_LT(friction[k], m * normal[k - 1]) << k;
        EXPECT_LT(x[k], 0.5 * -z[k]) << k;
        EXPECT_NEAR(shift[k], shift[1], eps_v) << k;
      }
      continue;
    }
    for (size_t k = 3; k < x.size(); ++k) {  // the third step on: no cutback before
      EXPECT_NEAR(friction[k], m * normal[k - 1], 1e-9 * normal[k - 1]) << k;
      EXPECT_NEAR(x[k], m * -z[k - 1], 0.02 * -z[k]) << k;
    }
    EXPECT_GT(shift.back() - shift[1], 10 * eps_v);
    // The friction traction at the faces' inner nodes: along +x on the lower face, -x on the
    // upper, and at most mu times the pressure (the lagged step's, lower).
    const std::string h5 = folder + "/" + tag + ".h5", last = "/step_7/";
    const auto X = hs_test::read_dataset(h5, "/mesh/coordinates");
    const auto t = hs_test::read_dataset(h5, last + "self_contact_friction");
    const auto p = hs_test::read_dataset(h5, last + "self_contact_pressure");
    int inner = 0;
    for (size_t n = 0; n < p.size(); ++n) {
      const double zn = X[3 * n + 2], xn = X[3 * n], yn = X[3 * n + 1];
      const bool lower = std::abs(zn - 0.05) < 1e-9, upper = std::abs(zn - 0.051) < 1e-9;
      if (!(lower || upper) || xn < 0.01 || xn > 0.09 || yn < 0.01 || yn > 0.09) continue;
      ++inner;
      EXPECT_GT(lower ? t[3 * n] : -t[3 * n], 0) << n;
      EXPECT_LT(std::hypot(t[3 * n], t[3 * n + 1]), m * p[n]) << n;
    }
    EXPECT_GT(inner, 20);
  }
  // A coefficient for a pair of surfaces replaces contact.friction there: mu 1 but 0.1 between
  // the two faces is the run with mu 0.1.
  const std::string deck = hs_test::write_deck(
      "drag_between.yaml",
      dragged_blocks("1.0, friction_between: [{surfaces: [lower_top, upper_bottom], friction: "
                     "0.1}]"));
  const Json s = hs_test::shared(run(deck, "drag_between", MPI_COMM_WORLD));
  // To Newton's tolerance: the same arithmetic, but round-off may end the two runs' Newton
  // at different iterations (2.4e-10 apart on the CI machine).
  EXPECT_NEAR(s["reactions_N"]["top"][0].get<double>(), slid, 1e-8 * slid);
}

// The block's mean x displacement at the last output step of a run of input/gripper_lift.yaml
// (rank 0): its nodes are those beyond the fingers' far wall (x > 78 mm) between them.
double block_drop(const std::string& h5, int step = 19) {
  const std::vector<double> X = hs_test::read_dataset(h5, "/mesh/coordinates");
  const std::vector<double> u =
      hs_test::read_dataset(h5, "/step_" + std::to_string(step) + "/displacement");
  double sum = 0;
  int count = 0;
  for (size_t n = 0; 3 * n < X.size(); ++n)
    if (X[3 * n] > 0.078 - 1e-9 && std::abs(X[3 * n + 1]) < 0.0095 + 1e-9) {
      sum += u[3 * n];
      ++count;
    }
  return sum / count;
}

// input/gripper_lift.yaml (at nu 0.45, faster): the fingers close on the block on its table,
// then the palm rises 10 mm. With friction between the fingers and the block the block rises
// with the palm and the table ends carrying nothing; without, the fingers slide up along the
// block and the table carries it. In every step the palm's reaction, the table's force and the
// weights of the silicone (growing with the first state's load factor) and of the water
// balance: the pairs' forces, friction included, are internal. 2 ranks give 1 rank's palm
// reaction.
TEST(SelfContact, TheGripperLiftsABlockOffItsTableByFriction) {
  const std::string shipped = kSource + "/input/gripper_lift.yaml";
  const double block_weight = 1070 * 9.81 * 0.016 * 0.019 * 0.016;
  auto lift = [&](const std::string& tag, const std::string& mu, MPI_Comm comm) {
    const std::vector<std::string> o = {"materials[0].nu=0.45", "materials[1].nu=0.45",
                                        "contact.friction=" + mu,
                                        "output.folder=" + (hs_test::test_folder() / tag).string()};
    return hs::run_simulation(hs::parse_deck(shipped, o), comm);
  };
  const Json held = hs_test::shared(lift("held", "0.8", MPI_COMM_WORLD));
  ASSERT_EQ(held["status"], "ok");
  const Json& grasped = held["states"][0]["contact"];
  EXPECT_GT(grasped["obstacles"][0]["force_N"][0].get<double>(), block_weight);  // on the table
  EXPECT_EQ(held["contact"]["obstacles"][0]["force_N"][0].get<double>(), 0);
  EXPECT_GT(held["contact"]["min_gap_m"].get<double>(), 0.009);  // 10 mm above the table
  EXPECT_GT(held["contact"]["self"]["friction_N"].get<double>(), block_weight);
  const double palm = held["reactions_N"]["base"][0];
  if (hs_test::world_rank() == 0) {
    const std::string folder = (hs_test::test_folder() / "held").string();
    EXPECT_NEAR(block_drop(folder + "/gripper_lift.h5"), -0.01, 5e-4);  // it rose with the palm
    const auto h = hs_test::read_history(folder);
    const auto& base = h.at("reaction_base_x_N");
    ASSERT_EQ(base.size(), 20u);
    // The silicone's weight per unit load factor (the grasp's tau, then 1), in every step.
    std::vector<double> solid;
    for (size_t k = 0; k < base.size(); ++k)
      solid.push_back((-base[k] + h.at("contact_table_x_N")[k] -
                       h.at("cavity_cavity_left_fluid_weight_N")[k] -
                       h.at("cavity_cavity_right_fluid_weight_N")[k]) /
                      std::min(1.0, (k + 1) / 10.0));
    for (size_t k = 0; k < solid.size(); ++k) EXPECT_NEAR(solid[k], solid.back(), 1e-8) << k;
  }
  if (hs_test::world_size() > 1) {
    Json one;
    if (hs_test::world_rank() == 0) one = lift("held_one", "0.8", MPI_COMM_SELF);
    one = hs_test::shared(one);
    EXPECT_NEAR(one["reactions_N"]["base"][0].get<double>(), palm, 1e-6 * -palm);
  }
  const Json slips = hs_test::shared(lift("slips", "0", MPI_COMM_WORLD));
  ASSERT_EQ(slips["status"], "ok");
  EXPECT_GT(slips["contact"]["obstacles"][0]["force_N"][0].get<double>(), 0.9 * block_weight);
  if (hs_test::world_rank() == 0)
    EXPECT_GT(block_drop((hs_test::test_folder() / "slips" / "gripper_lift.h5").string()), -1e-3);
}

// u: the upper block moved down into the barrier's reach (tilted and roughened, so that the
// pairs meet faces, edges and corners and the gaps differ); v: a random direction. Both depend
// on the nodes' places only, the same on any number of ranks.
void pressed_blocks(hs::Problem& problem, int64_t owned, Vec u, Vec v) {
  const double H = 0.05, g0 = 0.001, dhat = problem.self_contact()->barrier().distance;
  PetscScalar *ua, *va;
  VecGetArray(u, &ua);
  VecGetArray(v, &va);
  for (int64_t n = 0; n < owned; ++n) {
    const double x = problem.reference_coordinate(n, 0), y = problem.reference_coordinate(n, 1),
                 z = problem.reference_coordinate(n, 2);
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
  // The upper block shifted sideways, its symmetry planes' nodes too: with the blocks' edges
  // and corners aligned, pairs of edges lie exactly where their distance's kind changes (a
  // vertex's foot at the other edge's end), where the Hessian jumps and no difference
  // quotient matches it.
  VecGetArray(u, &ua);
  for (int64_t n = 0; n < owned; ++n)
    if (problem.reference_coordinate(n, 2) > H + 0.5 * g0) {
      ua[3 * n] += 0.05 * dhat;
      ua[3 * n + 1] += 0.03 * dhat;
    }
  VecRestoreArray(u, &ua);
}

// The tangent against central differences of the residual at the pressed blocks, along a
// random direction: the pairs' Hessians reach the assembled matrix whole, across ranks and
// through the pattern that grows.
TEST(SelfContact, TheTangentIsTheResidualsDerivativeWhereThePairsAct) {
  const std::string deck = hs_test::write_deck("tangent.yaml", blocks_deck(""));
  const hs::Config config = hs::parse_deck(deck, {});
  const hs::Distribution dist = hs::load_distributed_mesh(config.mesh, PETSC_COMM_WORLD);
  hs::Problem problem(config, dist, PETSC_COMM_WORLD);
  const double dhat = problem.self_contact()->barrier().distance;
  const hs::VecHandle u(problem.create_vector()), v(problem.create_vector());
  pressed_blocks(problem, dist.num_owned(), u, v);
  ASSERT_GT(problem.self_contact_totals(u).pairs, 50);
  ASSERT_GT(problem.self_contact_totals(u).min_gap, 0.3 * dhat);
  const hs::MatHandle J(problem.create_matrix());
  ASSERT_TRUE(problem.jacobian(u, 0.0, J));
  const hs_test::TangentCheck c = hs_test::check_tangent(problem, J, u, v, 0.0, 1e-4 * dhat);
  ASSERT_GE(c.error, 0) << "a residual failed";
  EXPECT_LT(c.error, 1e-6 * c.size) << c.error / c.size;
}

// The controller's force effector between two surfaces (`between`, docs/control.md): the force
// the upper block's face exerts on the lower's is the opposite of the lower's on the upper, it
// presses down, and the sum of the pairs' forces on the lower face's nodes (the residual's
// contact part there, from add_forces); its rows are its derivative (central differences along
// a random direction). Apart, the rows are a unit spring across the gap g0 that closes it.
TEST(SelfContact, TheForceBetweenTwoSurfacesAndItsRowsAreItsDerivative) {
  const std::string deck = hs_test::write_deck("between.yaml", blocks_deck(""));
  const hs::Config config = hs::parse_deck(deck, {});
  const hs::Distribution dist = hs::load_distributed_mesh(config.mesh, PETSC_COMM_WORLD);
  hs::Problem problem(config, dist, PETSC_COMM_WORLD);
  const double H = 0.05, g0 = 0.001, dhat = problem.self_contact()->barrier().distance;
  const int lower = 0, upper = 1;  // in contact.surfaces
  const hs::VecHandle u(problem.create_vector()), v(problem.create_vector());
  hs::VecHandle rows[3];
  for (auto& r : rows) r = hs::VecHandle(problem.create_vector());
  Vec r[3] = {rows[0], rows[1], rows[2]};

  // Apart: the gap is g0, and the spring's z row takes the faces' relative move.
  const hs::VecHandle closing(problem.create_vector());
  PetscScalar* ca;
  VecGetArray(closing, &ca);
  for (int64_t n = 0; n < dist.num_owned(); ++n)
    ca[3 * n + 2] = problem.reference_coordinate(n, 2) > H + 0.5 * g0 ? -0.5 : 0.5;
  VecRestoreArray(closing, &ca);
  EXPECT_NEAR(problem.self_contact_force_rows(u, upper, lower, r), g0, 1e-12);
  PetscScalar dot[3];
  for (int d = 0; d < 3; ++d) VecDot(r[d], closing, &dot[d]);
  EXPECT_NEAR(dot[2], -1.0, 1e-12);  // closing by 1 presses the lower face down by 1
  EXPECT_NEAR(dot[0], 0.0, 1e-12);
  EXPECT_NEAR(dot[1], 0.0, 1e-12);

  pressed_blocks(problem, dist.num_owned(), u, v);
  const std::array<double, 3> F = problem.self_contact_force(u, upper, lower);
  const std::array<double, 3> back = problem.self_contact_force(u, lower, upper);
  const double size = std::hypot(F[0], F[1], F[2]);
  ASSERT_GT(-F[2], 0.5 * size);  // it presses the lower face down
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(F[d], -back[d], 1e-12 * size) << d;
  // The residual's contact part on the lower block's nodes: the barrier's forces there.
  const hs::VecHandle R(problem.create_vector()), R0(problem.create_vector());
  ASSERT_TRUE(problem.residual(u, 0.0, R));
  const hs::VecHandle apart(problem.create_vector());  // u with the upper block lifted away
  VecCopy(u, apart);
  PetscScalar *aa, *rr, *r0;
  VecGetArray(apart, &aa);
  for (int64_t n = 0; n < dist.num_owned(); ++n)
    if (problem.reference_coordinate(n, 2) > H + 0.5 * g0) aa[3 * n + 2] += 0.1;
  VecRestoreArray(apart, &aa);
  ASSERT_TRUE(problem.residual(apart, 0.0, R0));
  double on_lower[3] = {0, 0, 0};
  VecGetArray(R, &rr);
  VecGetArray(R0, &r0);
  for (int64_t n = 0; n < dist.num_owned(); ++n)
    if (problem.reference_coordinate(n, 2) < H + 0.5 * g0)
      for (int d = 0; d < 3; ++d) on_lower[d] += rr[3 * n + d] - r0[3 * n + d];
  VecRestoreArray(R, &rr);
  VecRestoreArray(R0, &r0);
  MPI_Allreduce(MPI_IN_PLACE, on_lower, 3, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
  // The residual is dE/du: the force on the lower nodes is its negative; their elastic part
  // is the same at u and at `apart`, whose lower nodes did not move. Along z: the symmetry
  // planes leave the x and y rows of some of the face's nodes out of the residual.
  EXPECT_NEAR(F[2], -on_lower[2], 1e-9 * size);

  ASSERT_EQ(problem.self_contact_force_rows(u, upper, lower, r), 0.0);
  const double h = 1e-4 * dhat;
  const hs::VecHandle up(problem.create_vector()), down(problem.create_vector());
  VecWAXPY(up, h, v, u);
  VecWAXPY(down, -h, v, u);
  const std::array<double, 3> Fu = problem.self_contact_force(up, upper, lower);
  const std::array<double, 3> Fd = problem.self_contact_force(down, upper, lower);
  for (int d = 0; d < 3; ++d) {
    PetscScalar row_v;
    VecDot(r[d], v, &row_v);
    EXPECT_NEAR(row_v, (Fu[d] - Fd[d]) / (2 * h), 1e-6 * size / dhat) << d;
  }
}

// input/gripper_grasp_block.yaml at nu 0.45: the controller finds the two pressures that grasp
// the block with the forces asked of each finger (`between`, the y component), from 0.5 mm
// apart (the approach rows close the gap), then keeps a grasp of 0.08 N per finger while the
// palm rises 10 mm over two target sets (their `move`). Each answer meets its forces (the
// first, which closes the gap, to 5e-3 N, the lifting ones to 1e-3 N, the others to 1e-5 N), and
// the pairs' total force is the two grasps'; the block rises with the palm to 0.5 mm and leaves the
// table, which ends carrying nothing, the fingers' friction holding its weight; every state
// balances (the palm, the table and the weights in x; the palm and the table's friction in y, where
// the unequal grasp of the third set pushes the block); 2 ranks give 1 rank's pressures.
TEST(SelfContact, TheControllerGraspsABlockWithTheForcesAskedAndKeepsThemAsItLifts) {
  const std::string shipped = kSource + "/input/gripper_grasp_block.yaml";
  const double block_weight = 1070 * 9.81 * 0.016 * 0.019 * 0.016;
  auto grasp = [&](const std::string& tag, MPI_Comm comm) {
    const std::vector<std::string> o = {"materials[0].nu=0.45", "materials[1].nu=0.45",
                                        "output.folder=" + (hs_test::test_folder() / tag).string()};
    return hs::run_simulation(hs::parse_deck(shipped, o), comm);
  };
  const Json s = hs_test::shared(grasp("grasp_block", MPI_COMM_WORLD));
  ASSERT_EQ(s["status"], "ok");
  const Json& answers = s["targets"];
  ASSERT_EQ(answers.size(), 10u);  // 5 sets of 2 fingers
  for (size_t k = 0; k < answers.size(); ++k) {
    const Json& a = answers[k];
    // The first set closes the gap: the block's edges meet the skin's (edge pairs) before its
    // face meets a node, and its six steps end 3.3e-3 N off (1.6e-4 N with nodes against
    // triangles alone, contact.edges false).
    const double tolerance = k < 2 ? 5e-3 : k >= 6 ? 1e-3 : 1e-5;
    EXPECT_LT(a["error_N"].get<double>(), tolerance) << k;
    EXPECT_NEAR(a["reached"][1].get<double>(), a["target"][1].get<double>(), tolerance) << k;
    if (k % 2 == 0) {
      const double both = std::abs(a["reached"][1].get<double>()) +
                          std::abs(answers[k + 1]["reached"][1].get<double>());
      EXPECT_NEAR(a["contact"]["self"]["force_N"].get<double>(), both, 0.03 * both) << k;
    }
  }
  EXPECT_EQ(s["contact"]["obstacles"][0]["force_N"][0].get<double>(), 0);
  EXPECT_GT(s["contact"]["min_gap_m"].get<double>(), 0.009);  // 10 mm above the table
  EXPECT_GT(s["contact"]["self"]["friction_N"].get<double>(), block_weight);
  if (hs_test::world_rank() == 0) {
    const std::string folder = (hs_test::test_folder() / "grasp_block").string();
    EXPECT_NEAR(block_drop(folder + "/gripper_grasp_block.h5", s["outputs"].get<int>() - 1), -0.01,
                5e-4);
    const auto h = hs_test::read_history(folder);
    const auto& base = h.at("reaction_base_x_N");
    ASSERT_EQ(base.size(), 7u);  // 2 rest steps, 5 target sets
    std::vector<double> solid;   // the silicone's weight per unit load factor
    for (size_t k = 0; k < base.size(); ++k) {
      solid.push_back((-base[k] + h.at("contact_table_x_N")[k] -
                       h.at("cavity_cavity_left_fluid_weight_N")[k] -
                       h.at("cavity_cavity_right_fluid_weight_N")[k]) /
                      std::min(1.0, (k + 1) / 2.0));
      EXPECT_NEAR(h.at("reaction_base_y_N")[k], h.at("contact_table_y_N")[k], 1e-10) << k;
    }
    for (size_t k = 0; k < solid.size(); ++k) EXPECT_NEAR(solid[k], solid.back(), 1e-8) << k;
    EXPECT_LT(h.at("contact_table_y_N")[4], -0.005);  // the table holds the unequal grasp
  }
  if (hs_test::world_size() > 1) {
    Json one;
    if (hs_test::world_rank() == 0) one = grasp("grasp_block_one", MPI_COMM_SELF);
    one = hs_test::shared(one);
    for (size_t k = 0; k < answers.size(); ++k)
      for (int a = 0; a < 2; ++a)
        EXPECT_NEAR(one["targets"][k]["actuation"][a].get<double>(),
                    answers[k]["actuation"][a].get<double>(), 1e-6 * 4e4)
            << k;
  }
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

// Two bars turned so that a sharp edge of each faces the other, crossed at right angles
// (meshes/crossed_bars.geo): the lower clamped at its ends, the upper's ends moved down by
// 3 mm across the 1 mm gap. The ridges cross halfway between their nodes, where every node of
// either stays over 1.6 mm from the other's triangles (far beyond dhat, 86 um): only the pair
// of the two ridges' edges can hold them apart. The upper's ends take the force that the
// lower's clamps balance; the deformed ridges (read from the output) are still apart with the
// upper above the lower where they cross, within dhat; 2 ranks give 1 rank's force.
TEST(SelfContact, CrossedSharpEdgesPressOnEachOtherAndNeverPassThrough) {
  const std::string deck = hs_test::write_deck(
      "crossed.yaml", "mesh:\n  file: " + kSource +
                          "/meshes/crossed_bars.geo\n  order: 1\n"
                          "materials:\n"
                          "  - {group: body, model: linear_elastic, E: 1.0e5, nu: 0.3}\n"
                          "boundary:\n"
                          "  - {group: lower_ends}\n"
                          "  - {group: upper_ends, value: [0, 0, -0.003]}\n"
                          "contact: {surfaces: [lower_ridge, upper_ridge], self: true}\n"
                          "time: {type: static, steps: 8}\n");
  const Json s = hs_test::shared(run(deck, "crossed", MPI_COMM_WORLD));
  ASSERT_EQ(s["status"], "ok");
  const double upper = s["reactions_N"]["upper_ends"][2], lower = s["reactions_N"]["lower_ends"][2];
  EXPECT_GT(lower, 0.05);  // the lower's clamps hold it up against the contact's push
  EXPECT_NEAR(upper, -lower, 1e-7 * lower);
  const double dhat = s["contact"]["distance_m"], gap = s["contact"]["self"]["min_gap_m"];
  EXPECT_GT(gap, 0);
  EXPECT_LT(gap, dhat);
  if (hs_test::world_rank() == 0) {
    const std::string h5 = (hs_test::test_folder() / "crossed" / "crossed.h5").string();
    const std::string last = "/step_" + std::to_string(s["outputs"].get<int>() - 1);
    const std::vector<double> X = hs_test::read_dataset(h5, "/mesh/coordinates");
    const std::vector<double> u = hs_test::read_dataset(h5, last + "/displacement");
    // Each ridge's deformed nodes in order along it.
    std::vector<std::pair<double, Eigen::Vector3d>> ridge[2];
    for (size_t k = 0; 3 * k < X.size(); ++k) {
      const double x = X[3 * k], y = X[3 * k + 1], z = X[3 * k + 2];
      const Eigen::Vector3d at(x + u[3 * k], y + u[3 * k + 1], z + u[3 * k + 2]);
      if (std::abs(y) < 1e-9 && std::abs(z) < 1e-9) ridge[0].push_back({x, at});
      if (std::abs(x) < 1e-9 && std::abs(z - 0.001) < 1e-9) ridge[1].push_back({y, at});
    }
    ASSERT_EQ(ridge[0].size(), 8u);
    ASSERT_EQ(ridge[1].size(), 8u);
    for (auto& r : ridge)
      std::sort(r.begin(), r.end(), [](auto& a, auto& b) { return a.first < b.first; });
    // The nearest points of the two polylines on a grid of 200 points a segment.
    double best = 1e300;
    Eigen::Vector3d apart = Eigen::Vector3d::Zero();
    for (size_t i = 0; i + 1 < 8; ++i)
      for (size_t j = 0; j + 1 < 8; ++j)
        for (int a = 0; a <= 200; ++a)
          for (int b = 0; b <= 200; ++b) {
            const Eigen::Vector3d p =
                ridge[0][i].second + a / 200.0 * (ridge[0][i + 1].second - ridge[0][i].second);
            const Eigen::Vector3d q =
                ridge[1][j].second + b / 200.0 * (ridge[1][j + 1].second - ridge[1][j].second);
            if ((q - p).norm() < best) {
              best = (q - p).norm();
              apart = q - p;
            }
          }
    EXPECT_GT(apart(2), 0);  // the upper ridge is still above the lower
    EXPECT_LT(best, dhat);   // and presses on it
  }
  if (hs_test::world_size() > 1) {
    Json one;
    if (hs_test::world_rank() == 0) one = run(deck, "crossed_one", MPI_COMM_SELF);
    one = hs_test::shared(one);
    EXPECT_NEAR(one["reactions_N"]["lower_ends"][2].get<double>(), lower, 1e-6 * lower);
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
