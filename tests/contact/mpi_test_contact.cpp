// Contact with rigid obstacles on 1 and 2 ranks (docs/contact.md), against closed forms and
// conservation: a block pressed on a plane takes the uniaxial force of its compression, at a
// gap where the barrier's pressure is that force per area; a block resting on a floor puts
// its weight on it, and a sagging beam lands on one without a cutback; a sphere, a cylinder and a
// box pressed into a clamped block push on it with the clamp's reaction, no node of the body
// reaching them; the shipped finger pressing on a ball balances its base, its weight and the ball
// in every state; a block on an incline sticks below tan(theta) = mu and slides above it with its
// closed-form acceleration; the controller presses with the contact force asked for. On 2 ranks
// every force is compared with the same deck run on one.
#include <gtest/gtest.h>
#include <mpi.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../mpi_test_decks.hpp"
#include "common/error.hpp"
#include "contact/barrier.hpp"
#include "deck/deck.hpp"
#include "solvers/simulation.hpp"

namespace {
namespace mpi_test_contact {

using Json = nlohmann::json;
using hs_test::shared;
using hs_test::world_rank;
using hs_test::world_size;
using hs_test::write_deck;
const std::string kSource = HYDROSOFT_SOURCE_DIR;

// The run on every rank (with the deck's keys overridden by `sets`); on 2 ranks, its obstacle
// forces also against rank 0's run alone.
Json run(const std::string& deck, const std::string& tag, std::vector<std::string> sets = {}) {
  const std::string folder = (hs_test::test_folder() / tag).string();
  sets.push_back("output.folder=" + folder);
  const Json all = shared(hs::run_simulation(hs::parse_deck(deck, sets), MPI_COMM_WORLD));
  if (world_size() > 1) {
    Json one;
    sets.back() = "output.folder=" + folder + "_one";
    if (world_rank() == 0) one = hs::run_simulation(hs::parse_deck(deck, sets), MPI_COMM_SELF);
    one = shared(one);
    const auto& a = all["contact"]["obstacles"];
    const auto& b = one["contact"]["obstacles"];
    // The same to Newton's tolerance (1e-8 of the first residual), where each run stops.
    for (size_t o = 0; o < a.size(); ++o) {
      const auto& fb = b[o]["force_N"];
      const double scale =
          std::hypot(fb[0].get<double>(), fb[1].get<double>(), fb[2].get<double>());
      for (int d = 0; d < 3; ++d)
        EXPECT_NEAR(a[o]["force_N"][d].get<double>(), fb[d].get<double>(), 1e-6 * scale + 1e-12)
            << tag << " obstacle " << o;
    }
  }
  return all;
}

std::array<double, 3> obstacle_force(const Json& summary, int o) {
  const auto& f = summary["contact"]["obstacles"][o]["force_N"];
  return {f[0].get<double>(), f[1].get<double>(), f[2].get<double>()};
}

// The finger of input/finger_press.yaml (E 200 kPa, nu 0.45) above a ball of radius 10 mm at
// height ball_z, its tip height steered by its pressure (0-30 kPa, at most max_change a step);
// `control` adds the control section's targets and modes, `press` a contact-force effector
// of that name on the ball.
std::string finger_on_ball_deck(double ball_z, double max_change, const std::string& control,
                                const std::string& press = "") {
  return "mesh:\n  file: " + kSource +
         "/meshes/finger.geo\n  order: 1\n  parameters: {h: 0.004, ez: 0.003}\n"
         "materials:\n"
         "  - {group: body, model: neo_hookean, E: 2.0e5, nu: 0.45, density: 1070}\n"
         "boundary:\n  - {group: base}\n"
         "loads: {gravity: [0, 0, -9.81]}\n"
         "cavities:\n  - {group: cavity, kind: pneumatic}\n"
         "obstacles:\n"
         "  - {name: ball, type: sphere, center: [0.07, 0, " +
         std::to_string(ball_z) +
         "], radius: 0.01}\n"
         "contact: {surfaces: [outer, tip]}\n"
         "states:\n  - {name: rest, steps: 4}\n"
         "control:\n"
         "  effectors:\n    - {name: tip, point: effector, directions: [z]}\n" +
         (press.empty() ? "" : "    - {name: " + press + ", obstacle: ball, directions: [z]}\n") +
         "  actuators:\n"
         "    - {cavity: cavity, min_pressure: 0, max_pressure: 30000, max_pressure_change: " +
         std::to_string(max_change) + "}\n" + control;
}

// The finger of input/finger_pneumatic.yaml (inflation lifts it) resting under its weight on
// a ball, its tip steered to -9 mm (on the ball), up off it to -2 and -1.5 mm, and down onto
// it at -10 mm; `modes` ends the control section.
std::string finger_lifting_off_ball_deck(const std::string& modes) {
  return "mesh:\n  file: " + kSource +
         "/meshes/finger.geo\n  order: 1\n  parameters: {h: 0.004}\n"
         "materials:\n"
         "  - {group: body, model: neo_hookean, E: 2.0e5, nu: 0.45, density: 1070}\n"
         "boundary:\n  - {group: base}\nloads: {gravity: [0, 0, -9.81]}\n"
         "cavities:\n  - {group: cavity, kind: pneumatic}\n"
         "obstacles:\n  - {name: ball, type: sphere, center: [0.07, 0, -0.026], radius: 0.01}\n"
         "contact: {surfaces: [outer, tip]}\nstates:\n  - {name: rest, steps: 4}\n"
         "control:\n  effectors:\n    - {name: tip, point: effector, directions: [z]}\n"
         "  actuators:\n    - {cavity: cavity, min_pressure: 0, max_pressure: 30000}\n"
         "  targets:\n    - {tip: [0.09, 0, -0.009]}\n    - {tip: [0.09, 0, -0.002]}\n"
         "    - {tip: [0.09, 0, -0.0015]}\n    - {tip: [0.09, 0, -0.010]}\n" +
         modes;
}

std::string block_deck(const std::string& rest) {
  return "mesh:\n  file: " + kSource +
         "/meshes/block.geo\n  order: 1\n  parameters: {H: 0.1, h: 0.03}\n" + rest;
}

TEST(ObstacleContact, APressedBlockTakesTheUniaxialForceOfItsCompression) {
  // A linear elastic block H = 0.1 m, free to expand sideways (symmetry planes x0, y0), its
  // top moved down by delta onto a plane g0 below its bottom: the compression is delta - g0
  // + gap (the gap where the barrier holds it), uniform, so P1 is exact and the force is
  // E A (delta - g0 + gap) / H, and the barrier's pressure at that gap is the force per area.
  const double E = 1e5, H = 0.1, A = H * H, delta = 0.006, g0 = 0.001;
  const std::string deck = write_deck(
      "press.yaml", block_deck("materials:\n"
                               "  - {group: body, model: linear_elastic, E: 1.0e5, nu: 0.3}\n"
                               "boundary:\n"
                               "  - {group: top, components: [z], value: [0, 0, -0.006]}\n"
                               "  - {group: x0, components: [x]}\n"
                               "  - {group: y0, components: [y]}\n"
                               "obstacles:\n"
                               "  - {name: floor, type: plane, point: [0, 0, -0.001]}\n"
                               "contact: {surfaces: [bottom]}\n"
                               "time: {type: static, steps: 4}\n"));
  const Json s = run(deck, "press");
  const double gap = s["contact"]["min_gap_m"], dhat = s["contact"]["distance_m"],
               kappa = s["contact"]["stiffness_Pa_per_m"];
  ASSERT_GT(gap, 0);
  ASSERT_LT(gap, dhat);
  const auto f = obstacle_force(s, 0);
  const double F = E * A * (delta - g0 + gap) / H;
  EXPECT_NEAR(f[2], -F, 1e-8 * F);
  EXPECT_NEAR(f[0], 0, 1e-10 * F);
  EXPECT_NEAR(-kappa * hs::contact_barrier(gap, dhat).slope, F / A, 1e-6 * F / A);
  EXPECT_EQ(s["end_of_run"]["contact"], s["contact"]["obstacles"]);  // a static run's too
  // The same force, to Newton's tolerance (1e-8 of the first residual).
  EXPECT_NEAR(s["reactions_N"]["top"][2].get<double>(), f[2], 1e-7 * F);
  EXPECT_NEAR(s["contact"]["obstacles"][0]["area_m2"].get<double>(), A, 1e-12);
}

// The same block on P2: its consistent nodal forces load the faces' edge nodes and leave the
// corners almost nothing (a node's force over its area share is about 2 p and 0 in turn), and
// the pressure written is each face's mean, the uniaxial stress F / A again at every node away
// from the block's edges. The force is the closed form's between the smallest gap and dhat.
TEST(ObstacleContact, APressedP2BlockWritesTheUniaxialStressAsItsContactPressure) {
  const double E = 1e5, H = 0.1, A = H * H, delta = 0.006, g0 = 0.001;
  const std::string deck = write_deck(
      "press_p2.yaml", block_deck("materials:\n"
                                  "  - {group: body, model: linear_elastic, E: 1.0e5, nu: 0.3}\n"
                                  "boundary:\n"
                                  "  - {group: top, components: [z], value: [0, 0, -0.006]}\n"
                                  "  - {group: x0, components: [x]}\n"
                                  "  - {group: y0, components: [y]}\n"
                                  "obstacles:\n"
                                  "  - {name: floor, type: plane, point: [0, 0, -0.001]}\n"
                                  "contact: {surfaces: [bottom]}\n"
                                  "time: {type: static, steps: 4}\n"));
  const Json s = run(deck, "press_p2", {"mesh.order=2"});
  const double gap = s["contact"]["min_gap_m"], dhat = s["contact"]["distance_m"];
  ASSERT_GT(gap, 0);
  ASSERT_LT(gap, dhat);
  const double F = -obstacle_force(s, 0)[2];
  EXPECT_GT(F, E * A * (delta - g0 + gap) / H);
  EXPECT_LT(F, E * A * (delta - g0 + dhat) / H);
  EXPECT_NEAR(s["reactions_N"]["top"][2].get<double>(), -F, 1e-7 * F);
  if (world_rank() == 0) {
    const std::string h5 = (hs_test::test_folder() / "press_p2" / "press_p2.h5").string();
    const std::string last = "/step_" + std::to_string(s["outputs"].get<int>() - 1);
    const auto X = hs_test::read_dataset(h5, "/mesh/coordinates");
    const auto p = hs_test::read_dataset(h5, last + "/contact_pressure");
    int inner = 0;
    for (size_t n = 0; n < p.size(); ++n) {
      const double x = X[3 * n], y = X[3 * n + 1];
      if (std::abs(X[3 * n + 2]) > 1e-9 || x < 0.005 || x > 0.095 || y < 0.005 || y > 0.095)
        continue;
      ++inner;
      EXPECT_NEAR(p[n], F / A, 0.1 * F / A) << n;  // 0 or 2 F / A without the faces' means
    }
    EXPECT_GT(inner, 20);
  }
}

TEST(ObstacleContact, ABlockRestingOnAFloorPutsItsWeightOnIt) {
  // Held by the barrier alone along z (its bottom starts half a dhat above the floor).
  const double rho = 1000, g = 9.81, H = 0.1;
  const double dhat = 1e-4;
  const std::string deck = write_deck(
      "rest.yaml",
      block_deck("materials:\n"
                 "  - {group: body, model: neo_hookean, E: 1.0e5, nu: 0.45, density: 1000}\n"
                 "boundary:\n"
                 "  - {group: x0, components: [x]}\n"
                 "  - {group: y0, components: [y]}\n"
                 "loads: {gravity: [0, 0, -9.81]}\n"
                 "obstacles:\n"
                 "  - {name: floor, type: plane, point: [0, 0, -5.0e-5], normal: [0, 0, 2]}\n"
                 "contact: {surfaces: [bottom, sides], distance: 1.0e-4}\n"
                 "time: {type: static, steps: 2}\n"));
  const Json s = run(deck, "rest");
  const auto f = obstacle_force(s, 0);
  const double weight = rho * g * H * H * H;
  EXPECT_NEAR(f[2], -weight, 1e-7 * weight);  // to Newton's tolerance
  EXPECT_NEAR(std::hypot(f[0], f[1]), 0, 1e-12 * weight);
  const double gap = s["contact"]["min_gap_m"];
  EXPECT_GT(gap, 0);
  EXPECT_LT(gap, dhat);
}

TEST(ObstacleContact, ABeamSaggingOntoAFloorLandsWithoutACutbackAndBalancesItsWeight) {
  // A cantilever under its own weight over a floor it reaches in the second step. The step's
  // predicted start (the first step's increment extrapolated) and Newton's l2 line search
  // both overshoot through the floor: each is shortened to keep a tenth of the gaps
  // (Problem::keep_outside_contact, NewtonSolver::limit_answer) instead of failing the residual
  // and cutting the step back (6 cutbacks before). The clamp and the floor carry the weight.
  const double rho = 1070, g = 9.81, L = 0.1, h = 0.01;
  const std::string deck = write_deck(
      "sag.yaml", "mesh:\n  file: " + kSource +
                      "/meshes/cantilever.geo\n  order: 1\n"
                      "  parameters: {L: 0.1, h: 0.01, n: 2}\n"
                      "materials:\n"
                      "  - {group: body, model: linear_elastic, E: 1.0e6, nu: 0.45, "
                      "density: 1070}\n"
                      "boundary:\n  - {group: clamped}\n"
                      "loads: {gravity: [0, 0, -9.81]}\n"
                      "obstacles:\n  - {name: floor, type: plane, point: [0, 0, -0.010]}\n"
                      "contact: {surfaces: [bottom], distance: 2.0e-4}\n"
                      "time: {type: static, steps: 2}\n");
  const Json s = run(deck, "sag");
  EXPECT_EQ(s["cutbacks"].get<int>(), 0);
  const auto f = obstacle_force(s, 0);
  const double weight = rho * g * L * h * h;
  EXPECT_LT(f[2], -0.05 * weight);  // it landed
  EXPECT_NEAR(s["reactions_N"]["clamped"][2].get<double>() - f[2], weight, 1e-7 * weight);
  const double gap = s["contact"]["min_gap_m"];
  EXPECT_GT(gap, 0);
  EXPECT_LT(gap, s["contact"]["distance_m"].get<double>());
}

// The sum over the nodes of an output step's nodal_load (gravity and the cavity's pressure,
// which sums to zero over its closed walls).
std::array<double, 3> total_load(const std::string& h5, int step) {
  std::array<double, 3> total{0, 0, 0};
  const auto load = hs_test::read_dataset(h5, "/step_" + std::to_string(step) + "/nodal_load");
  for (size_t i = 0; i < load.size(); ++i) total[i % 3] += load[i];
  return total;
}

// In each state the body's forces balance: the base's reaction, the applied load and the
// obstacle's push on it (minus the body's force on the obstacle); it presses harder as the
// pressure rises, and no node reaches the obstacle.
void expect_finger_presses(const std::string& name) {
  const std::string folder = (hs_test::test_folder() / name).string();
  const Json s = run(kSource + "/input/" + name + ".yaml", name);
  double previous = 0;
  for (const auto& state : s["states"]) {
    const auto& f = state["contact"]["obstacles"][0]["force_N"];
    const auto& base = state["reactions_N"]["base"];
    const auto load = total_load(folder + "/" + name + ".h5", state["step"].get<int>());
    const double scale = std::abs(f[2].get<double>());
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(base[d].get<double>() + load[d] - f[d].get<double>(), 0, 1e-7 * scale)
          << name << " " << state["name"] << " " << d;
    EXPECT_GT(scale, previous) << name << " " << state["name"];
    previous = scale;
    EXPECT_GT(state["contact"]["min_gap_m"].get<double>(), 0);
  }
}

TEST(ObstacleContact, TheShippedFingerPressesABallWithWhatItsBaseAndWeightLeave) {
  expect_finger_presses("finger_press");
}

// The same finger on a non-convex surface read from an STL file (meshes/peanut.stl).
TEST(ObstacleContact, TheShippedFingerPressesAnStlObjectWithWhatItsBaseAndWeightLeave) {
  expect_finger_presses("finger_press_peanut");
}

// history.csv's rows as {column: value}.
std::vector<std::map<std::string, double>> history(const std::string& folder) {
  std::ifstream in(folder + "/history.csv");
  std::string header, line;
  std::getline(in, header);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream names(header), values(line);
    std::string name, value;
    rows.emplace_back();
    while (std::getline(names, name, ',') && std::getline(values, value, ','))
      rows.back()[name] = std::stod(value);
  }
  return rows;
}

// A block (nu = 0: no sideways swelling to tilt the slip) clamped to a plate that comes down
// onto a floor with friction and drags it sideways by `drag`.
std::string dragged_block(const std::string& drag, const std::string& mu) {
  return block_deck(
      "materials:\n"
      "  - {group: body, model: linear_elastic, E: 1.0e5, nu: 0.0}\n"
      "boundary:\n"
      "  - {group: top, value: [" +
      drag +
      ", 0, -0.004]}\n"
      "obstacles:\n"
      "  - {name: floor, type: plane, point: [0, 0, -0.001], friction: " +
      mu +
      "}\n"
      "contact: {surfaces: [bottom]}\n"
      "time: {type: static, steps: 8}\n");
}

TEST(ObstacleContact, ASlidingBlockDragsTheFloorWithMuTimesItsNormalForce) {
  // Dragged 10 mm, the block slides: each step's friction is mu times the normal force it
  // started with (lagged), and the plate's reaction balances it.
  const std::string folder = (hs_test::test_folder() / "slide").string();
  run(write_deck("slide.yaml", dragged_block("0.01", "0.3")), "slide");
  const auto rows = history(folder);
  ASSERT_EQ(rows.size(), 8u);
  for (size_t k = 3; k < rows.size(); ++k) {
    const double fx = rows[k].at("contact_floor_x_N");
    const double normal_before = -rows[k - 1].at("contact_floor_z_N");
    EXPECT_NEAR(fx, 0.3 * normal_before, 1e-5 * fx) << "row " << k;
    EXPECT_NEAR(rows[k].at("reaction_top_x_N"), fx, 1e-8 * fx) << "row " << k;
  }
  // The last step's fields: every node's gap is its height above the floor; the bottom's
  // nodes are pressed and dragged back (the floor's traction on the body along -x), the
  // others carry nothing.
  if (world_rank() != 0) return;
  const std::string h5 = folder + "/slide.h5", step = "/step_7/";
  const auto X = hs_test::read_dataset(h5, "/mesh/coordinates"),
             u = hs_test::read_dataset(h5, step + "displacement");
  const auto gap = hs_test::read_dataset(h5, step + "contact_gap"),
             p = hs_test::read_dataset(h5, step + "contact_pressure");
  const auto t = hs_test::read_dataset(h5, step + "friction_traction");
  ASSERT_EQ(gap.size(), X.size() / 3);
  for (size_t n = 0; n < gap.size(); ++n) {
    EXPECT_NEAR(gap[n], X[3 * n + 2] + u[3 * n + 2] + 0.001, 1e-15) << n;
    const bool bottom = std::abs(X[3 * n + 2]) < 1e-12;
    if (bottom) {
      EXPECT_GT(p[n], 0) << n;
      EXPECT_LT(t[3 * n], 0) << n;
      EXPECT_LE(std::hypot(t[3 * n], t[3 * n + 1]), 0.3 * 1.2 * p[n]) << n;
    } else {
      EXPECT_EQ(p[n], 0) << n;
      EXPECT_EQ(t[3 * n], 0) << n;
    }
  }
}

TEST(ObstacleContact, AStickingBlockStaysWhereItTouched) {
  // Dragged 2 mm with mu = 1, the block's shear stays below mu N: once it has touched, its
  // bottom does not slip by more than contact.slip (no creep from step to step).
  const std::string folder = (hs_test::test_folder() / "stick").string();
  const Json s = run(write_deck("stick.yaml", dragged_block("0.002", "1.0")), "stick");
  const auto rows = history(folder);
  const double eps_v = 0.1 * s["contact"]["distance_m"].get<double>();
  const auto f = obstacle_force(s, 0);
  EXPECT_GT(f[0], 1.0);
  EXPECT_LT(f[0], 0.5 * -f[2]);
  // The bottom's nodes' x displacements per output step, from the .h5.
  const std::string h5 = folder + "/stick.h5";
  const std::vector<double> X = hs_test::read_dataset(h5, "/mesh/coordinates");
  std::vector<double> touched;  // each bottom node's x at the first step in contact
  for (size_t k = 0; k < rows.size(); ++k) {
    if (rows[k].at("contact_floor_z_N") == 0) continue;
    const std::vector<double> u =
        hs_test::read_dataset(h5, "/step_" + std::to_string(k) + "/displacement");
    size_t b = 0;
    for (size_t n = 0; 3 * n < X.size(); ++n) {
      if (std::abs(X[3 * n + 2]) > 1e-12) continue;
      if (touched.size() <= b) touched.push_back(u[3 * n]);
      EXPECT_NEAR(u[3 * n], touched[b], eps_v) << "step " << k << " node " << n;
      ++b;
    }
  }
  EXPECT_GT(touched.size(), 10u);
}

// The block's mean x displacement per output step, from the .h5 (rank 0).
std::vector<double> mean_x(const std::string& h5, size_t steps) {
  std::vector<double> x;
  for (size_t k = 0; k < steps; ++k) {
    const auto u = hs_test::read_dataset(h5, "/step_" + std::to_string(k) + "/displacement");
    double sum = 0;
    for (size_t n = 0; 3 * n < u.size(); ++n) sum += u[3 * n];
    x.push_back(sum / (u.size() / 3));
  }
  return x;
}

TEST(ObstacleContact, ABlockOnAnInclineSticksBelowMuAndSlidesAboveWithItsAcceleration) {
  // input/block_on_incline.yaml: a free 1 kg block on a floor with mu = 0.5, gravity tilted by
  // theta (the incline), in implicit dynamics. tan 35 deg = 0.70 > mu (the deck): it slides
  // with a = g (sin(theta) - mu cos(theta)) and friction is mu times the normal force
  // m g cos(theta); tan 20 deg = 0.36 < mu: it comes to rest and friction holds m g sin(theta).
  const double g = 9.81, mu = 0.5, m = 1000 * 0.1 * 0.1 * 0.1, dt = 0.01;
  for (double theta_deg : {20.0, 35.0}) {
    const std::string tag = "block_on_incline" + std::to_string(static_cast<int>(theta_deg));
    const std::string folder = (hs_test::test_folder() / tag).string();
    const double theta = theta_deg * M_PI / 180;
    char gravity[80];
    std::snprintf(gravity, sizeof gravity, "loads.gravity=[%.17g, 0, %.17g]", g * std::sin(theta),
                  -g * std::cos(theta));
    run(kSource + "/input/block_on_incline.yaml", tag, {gravity});
    const auto rows = history(folder);
    ASSERT_EQ(rows.size(), 21u);
    const auto& end = rows.back();
    EXPECT_NEAR(-end.at("contact_incline_z_N"), m * g * std::cos(theta), 1e-6) << tag;
    const bool slides = theta_deg > 30;
    EXPECT_NEAR(end.at("contact_incline_x_N"),
                slides ? mu * m * g * std::cos(theta) : m * g * std::sin(theta), 1e-6)
        << tag;
    if (world_rank() != 0) continue;
    const auto x = mean_x(folder + "/block_on_incline.h5", rows.size());
    const size_t n = x.size();
    const double a = (x[n - 1] - 2 * x[n - 2] + x[n - 3]) / (dt * dt);
    if (slides) {
      EXPECT_NEAR(a, g * (std::sin(theta) - mu * std::cos(theta)), 1e-5) << tag;
      EXPECT_GT(x[n - 1], 0.03) << tag;
    } else {
      EXPECT_NEAR(x[n - 1], x[n - 6], 1e-9) << tag;  // at rest
      EXPECT_LT(x[n - 1], 1e-4) << tag;              // the shear's and eps_v's creep
    }
  }
}

TEST(ObstacleContact, ABallPressedOnAPlaneHasHertzsPressure) {
  // input/hertz_contact.yaml: a quarter of an elastic hemisphere (R 10 mm, E 100 kPa, nu 0.3)
  // pressed on a plane. Its contact pressure field against Hertz's p0 sqrt(1 - r^2 / a^2) for
  // the force the plane takes, a = (3 F R / (4 E*))^(1/3): within 3 % of p0 at the pole and on
  // rings of the ball's surface (mean over the ring's nodes); the barrier's distance (10 um,
  // a tenth of the indentation) keeps the computed pressure 1-3 % low, 1 % with 4 um.
  const std::string folder = (hs_test::test_folder() / "hertz").string();
  const Json s = run(kSource + "/input/hertz_contact.yaml", "hertz");
  const double R = 0.01, E_star = 1e5 / (1 - 0.3 * 0.3);
  const double quarter = -obstacle_force(s, 0)[2];
  EXPECT_NEAR(s["reactions_N"]["top"][2].get<double>(), -quarter, 1e-8 * quarter);
  const double F = 4 * quarter, a = std::cbrt(3 * F * R / (4 * E_star));
  const double p0 = 3 * F / (2 * M_PI * a * a);
  EXPECT_GT(a, 0.001);  // several elements across the contact (hc = 0.1 mm)
  if (world_rank() != 0) return;
  const std::string h5 = folder + "/hertz_contact.h5";
  const auto X = hs_test::read_dataset(h5, "/mesh/coordinates");
  const int last = s["outputs"].get<int>() - 1;
  const auto p = hs_test::read_dataset(h5, "/step_" + std::to_string(last) + "/contact_pressure");
  for (double ring : {0.0, 0.2, 0.4, 0.6, 0.8, 0.9}) {
    double sum = 0;
    int count = 0;
    for (size_t n = 0; n < p.size(); ++n) {
      const double r = std::hypot(X[3 * n], X[3 * n + 1]);
      const double from_centre = std::hypot(r, X[3 * n + 2]);
      if (std::abs(from_centre - R) > 1e-6 * R || std::abs(r - ring * a) > 0.08 * a) continue;
      sum += p[n];
      ++count;
    }
    ASSERT_GT(count, 0) << ring;
    EXPECT_NEAR(sum / count / p0, std::sqrt(1 - ring * ring), 0.03) << "r = " << ring << " a";
  }
  // Beyond the contact radius and its barrier's reach, nothing.
  for (size_t n = 0; n < p.size(); ++n)
    if (std::hypot(X[3 * n], X[3 * n + 1]) > 1.3 * a) EXPECT_EQ(p[n], 0) << n;
}

TEST(ObstacleContact, AnObstacleThatStartsInsideTheBodyIsRefusedBeforeAnyWork) {
  // A ball whose bottom is 5 mm below the block's top face: named, with how deep the body's
  // surface reaches into it and where, on every rank.
  const std::string deck = write_deck(
      "overlap.yaml", block_deck("materials:\n"
                                 "  - {group: body, model: neo_hookean, E: 1.0e5, nu: 0.45}\n"
                                 "boundary:\n"
                                 "  - {group: bottom}\n"
                                 "obstacles:\n"
                                 "  - {name: floor, type: plane, point: [0, 0, -1]}\n"
                                 "  - {name: ball, type: sphere, center: [0.05, 0.05, 0.125], "
                                 "radius: 0.03}\n"
                                 "contact: {surfaces: [top]}\n"));
  const std::string folder = (hs_test::test_folder() / "overlap").string();
  try {
    hs::run_simulation(hs::parse_deck(deck, {"output.folder=" + folder}), MPI_COMM_WORLD);
    ADD_FAILURE() << "no error";
  } catch (const hs::InputError& e) {
    const std::string message = e.what(),
                      head = deck +
                             ": obstacles[1] ('ball'): the undeformed body's contact "
                             "surface reaches ";
    ASSERT_EQ(message.rfind(head, 0), 0u) << message;
    // The deepest node of the top face: at most the 5 mm of its centre, and in it.
    const double depth = std::stod(message.substr(head.size()));
    EXPECT_GT(depth, 0) << message;
    EXPECT_LE(depth, 0.005 + 1e-12) << message;
    EXPECT_NE(message.find(" m into it at ("), std::string::npos) << message;
  }
}

TEST(ObstacleContact, TheControllerSteersAFingerThatTouchesABall) {
  // The finger of input/finger_press.yaml, its tip height steered by its pressure: the
  // controller's compliance includes the barrier. A target above the ball is reached; one
  // below the ball's top cannot be, and the pressure saturates at its bound with the finger
  // held on the ball.
  const std::string deck =
      write_deck("control.yaml",
                 finger_on_ball_deck(-0.0185, 5000,
                                     "  targets:\n    - {tip: [0.09, 0.0, -0.002]}\n"
                                     "    - {tip: [0.09, 0.0, -0.004]}\n  steps_per_target: 5\n"));
  const Json s = run(deck, "control");
  const auto& targets = s["targets"];
  ASSERT_EQ(targets.size(), 2u);
  EXPECT_LT(targets[0]["error_m"].get<double>(), 1e-4);
  EXPECT_FALSE(targets[0]["saturated"][0].get<bool>());
  EXPECT_TRUE(targets[1]["saturated"][0].get<bool>());
  EXPECT_NEAR(targets[1]["actuation"][0].get<double>(), 30000, 1e-6);
  EXPECT_GT(targets[1]["reached"][2].get<double>(), -0.004 + 1e-4);  // held up by the ball
  EXPECT_LT(obstacle_force(s, 0)[2], -0.1);
  EXPECT_GT(s["contact"]["min_gap_m"].get<double>(), 0);
  // Each answer carries the obstacles' forces where it left the body: the last one's are the
  // run's end, and the first target's pressure pushes the ball less than the bound's.
  EXPECT_EQ(s["end_of_run"]["contact"], s["contact"]["obstacles"]);
  EXPECT_TRUE(s["end_of_run"].contains("cavities"));
  for (int d = 0; d < 3; ++d)
    EXPECT_DOUBLE_EQ(targets[1]["contact"]["obstacles"][0]["force_N"][d].get<double>(),
                     obstacle_force(s, 0)[d]);
  EXPECT_GT(targets[0]["contact"]["obstacles"][0]["force_N"][2].get<double>(),
            obstacle_force(s, 0)[2]);
}

TEST(ObstacleContact, TheRealTimeModeAnswersEveryTargetAsTheFingerPressesTheBall) {
  // The same finger resting on a ball 2 mm lower, steered by the real-time step (one_step, one
  // step a target, 10 kPa at most a step) up and down against it. A linearised step that
  // carried a node into the ball (where the barrier is infinite) made the next residual
  // impossible and ended the run at the second target; now such a step is shortened and taken
  // again with the free configuration converged (the open-close test below meets it), and a
  // free step after the correction that would enter the ball makes the answer the
  // equilibrium at the correction's pressure (it had been the correction, 0.1 mm off). Every
  // answer lies at the equilibrium of its pressure within the refinement's 0.01 mm.
  std::string targets;
  for (double z : {-0.002, -0.0045, -0.0015, -0.006, -0.002, -0.005, -0.004, -0.0055})
    targets += "    - {tip: [0.09, 0.0, " + std::to_string(z) + "]}\n";
  const std::string deck = write_deck(
      "realtime.yaml", finger_on_ball_deck(-0.0205, 10000,
                                           "  targets:\n" + targets +
                                               "  steps_per_target: 1\n  free_solve: one_step\n"
                                               "  check_equilibrium: true\n"));
  const Json s = run(deck, "realtime");
  const auto& answers = s["targets"];
  ASSERT_EQ(answers.size(), 8u);
  int settled = 0;
  for (const auto& t : answers) {
    EXPECT_NEAR(t["reached"][2].get<double>(), t["equilibrium"][2].get<double>(), 2e-5) << t.dump();
    settled += t.value("fallback", "").find("the answer is the equilibrium") != std::string::npos;
  }
  EXPECT_GE(settled, 1);
  // The last target, 10 kPa above the one before, is met to the equilibrium's 0.01 mm.
  EXPECT_NEAR(answers[7]["reached"][2].get<double>(), answers[7]["equilibrium"][2].get<double>(),
              1e-5);
  EXPECT_GT(s["contact"]["min_gap_m"].get<double>(), 0);
}

TEST(ObstacleContact, TheControllerPressesTheBallWithTheForceAskedFor) {
  // "Press this object with 0.17 N": a contact-force effector, its row the force's derivative
  // (the barrier's per-obstacle Hessians) through the compliance. The finger rests on the
  // ball with 0.124 N under its weight; 0.17 N and then 0.14 N are asked for. What it reached
  // is the force on the ball, and the base's reaction and the body's weight balance it: the
  // clamp measures the same force independently of the barrier's sums.
  const std::string folder = (hs_test::test_folder() / "press").string();
  const std::string deck = write_deck(
      "press.yaml", finger_on_ball_deck(-0.0185, 10000,
                                        "  targets:\n    - {press: [0, 0, -0.17]}\n"
                                        "    - {press: [0, 0, -0.14]}\n  steps_per_target: 4\n",
                                        "press"));
  const Json s = run(deck, "press");
  const auto& targets = s["targets"];
  ASSERT_EQ(targets.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    const double asked = k == 0 ? -0.17 : -0.14;
    EXPECT_NEAR(targets[k]["reached"][2].get<double>(), asked, 1e-5) << targets[k].dump();
    EXPECT_LT(targets[k]["error_N"].get<double>(), 1e-5);
    EXPECT_FALSE(targets[k].contains("error_m"));
    EXPECT_NEAR(targets[k]["contact"]["obstacles"][0]["force_N"][2].get<double>(),
                targets[k]["reached"][2].get<double>(), 1e-12);
    EXPECT_FALSE(targets[k]["saturated"][0].get<bool>());
  }
  // Pressing harder took more pressure.
  EXPECT_GT(targets[0]["actuation"][0].get<double>(), targets[1]["actuation"][0].get<double>());
  const auto f = obstacle_force(s, 0);
  const auto& base = s["reactions_N"]["base"];
  const auto load = total_load(folder + "/press.h5", targets[1]["step"].get<int>());
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(base[d].get<double>() + load[d] - f[d], 0, 1e-7 * std::abs(f[2])) << d;
  EXPECT_NEAR(f[2], -0.14, 1e-5);
  EXPECT_GT(s["contact"]["min_gap_m"].get<double>(), 0);
}

TEST(ObstacleContact, TheControllerPressesAndSteersWithFriction) {
  // The finger on the ball with Coulomb friction mu = 0.5: friction's lag is taken at each
  // control step's end (the controller's trial and check solves do not move it: held, a
  // pressed step took 116 and a steered one 307 Newton iterations against 51 and 16 now, 10
  // and 8 without friction), and the force effector's rows carry
  // friction's stiffness. Pressed with 0.17 N, then its tip steered up to -3 mm: both met, and
  // the ball's force, friction included, balances the base and the weight.
  std::string deck = finger_on_ball_deck(
      -0.0185, 10000,
      "  targets:\n    - {press: [0, 0, -0.17]}\n    - {tip: [0.09, 0.0, -0.003]}\n"
      "  steps_per_target: 4\n",
      "press");
  deck.replace(deck.find("radius: 0.01}"), 13, "radius: 0.01, friction: 0.5}");
  const std::string folder = (hs_test::test_folder() / "friction").string();
  const Json s = run(write_deck("friction.yaml", deck), "friction");
  const auto& targets = s["targets"];
  ASSERT_EQ(targets.size(), 2u);
  EXPECT_NEAR(targets[0]["reached"][2].get<double>(), -0.17, 3e-5) << targets[0].dump();
  EXPECT_LT(targets[1]["error_m"].get<double>(), 1e-4) << targets[1].dump();
  const auto f = obstacle_force(s, 0);
  const auto& base = s["reactions_N"]["base"];
  const auto load = total_load(folder + "/friction.h5", targets[1]["step"].get<int>());
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(base[d].get<double>() + load[d] - f[d], 0, 1e-7 * std::abs(f[2])) << d;
  EXPECT_GT(s["contact"]["min_gap_m"].get<double>(), 0);
}

TEST(ObstacleContact, TheRealTimeModePressesTheBallWithTheForceAskedFor) {
  // The same force targets in the real-time step (one step a target, refined), up and down:
  // every answer is the equilibrium of its pressure and presses with the force asked for.
  std::string targets;
  for (double f : {-0.135, -0.15, -0.14, -0.16})
    targets += "    - {press: [0, 0, " + std::to_string(f) + "]}\n";
  const std::string deck =
      write_deck("press_realtime.yaml",
                 finger_on_ball_deck(-0.0185, 10000,
                                     "  targets:\n" + targets +
                                         "  steps_per_target: 1\n  free_solve: one_step\n"
                                         "  check_equilibrium: true\n",
                                     "press"));
  const Json s = run(deck, "press_realtime");
  const auto& answers = s["targets"];
  ASSERT_EQ(answers.size(), 4u);
  for (const auto& t : answers) {
    const double asked = t["target"][2].get<double>();
    EXPECT_NEAR(t["equilibrium"][2].get<double>(), asked, 2e-4) << t.dump();
    EXPECT_NEAR(t["reached"][2].get<double>(), asked, 2e-4) << t.dump();
    EXPECT_TRUE(t.contains("equilibrium_error_N"));
  }
}

TEST(ObstacleContact, TheRealTimeModeAnswersEquilibriaAsContactOpensAndCloses) {
  // The finger of input/finger_pneumatic.yaml (cavity below the mid-plane: inflation lifts
  // it) resting under its weight on a ball, its tip steered up off the ball and down onto it
  // again, one real-time step a target: a linearisation made with the contact open does not
  // know the ball (or with it closed, that it lets go), and a finger landing on the ball
  // from above had its answer 6.6 mm from its equilibrium. Now every answer is the
  // equilibrium at its pressure.
  const std::string deck =
      write_deck("open_close.yaml",
                 finger_lifting_off_ball_deck(
                     "  steps_per_target: 1\n  free_solve: one_step\n  check_equilibrium: true\n"));
  const Json s = run(deck, "open_close");
  const auto& answers = s["targets"];
  ASSERT_EQ(answers.size(), 4u);
  for (const auto& t : answers)
    EXPECT_NEAR(t["reached"][2].get<double>(), t["equilibrium"][2].get<double>(), 1e-6) << t.dump();
  auto pressing = [&](int k) {
    return answers[k]["contact"]["obstacles"][0]["force_N"][2].get<double>() < 0;
  };
  EXPECT_TRUE(pressing(0));   // on the ball
  EXPECT_FALSE(pressing(2));  // lifted off it (at the second step up)
  EXPECT_TRUE(pressing(3));   // landed on it again
}

// Each finger's grasp force: the y component of its skin's force on the ball.
double grasp(const Json& answer) { return answer["reached"][1].get<double>(); }

TEST(ObstacleContact, TheGripperGraspsTheBallWithTheForceAskedOfEachFinger) {
  // input/gripper_grasp.yaml: two silicone fingers (nodal-pressure element) start 0.5 mm from
  // the ball, close on it (the force rows are a spring across the gap until they touch) and
  // press with 0.04, then 0.08 N each, then 0.06 and 0.03 N. The two fingers' forces are sums
  // over disjoint surfaces: together they are the ball's force, and the palm's reaction
  // balances it with the weight.
  const std::string folder = (hs_test::test_folder() / "gripper").string();
  const Json s = run(kSource + "/input/gripper_grasp.yaml", "gripper");
  const auto& answers = s["targets"];
  ASSERT_EQ(answers.size(), 6u);
  for (const auto& t : answers) {
    EXPECT_NEAR(grasp(t), t["target"][1].get<double>(), 1e-6) << t.dump();
    EXPECT_EQ(t["effector"] == "grip_left", grasp(t) < 0) << t.dump();
  }
  const auto ball = obstacle_force(s, 0);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(answers[4]["reached"][d].get<double>() + answers[5]["reached"][d].get<double>(),
                ball[d], 1e-12)
        << d;
  EXPECT_NEAR(ball[1], -0.03, 1e-6);
  const auto& base = s["reactions_N"]["base"];
  const auto load = total_load(folder + "/gripper_grasp.h5", answers[5]["step"].get<int>());
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(base[d].get<double>() + load[d] - ball[d], 0, 1e-7 * std::abs(load[0])) << d;
  // Asked to press harder, each finger took more pressure.
  EXPECT_GT(answers[2]["actuation"][0].get<double>(), answers[0]["actuation"][0].get<double>());
  EXPECT_GT(answers[2]["actuation"][1].get<double>(), answers[0]["actuation"][1].get<double>());
  EXPECT_GT(s["contact"]["min_gap_m"].get<double>(), 0);
}

TEST(ObstacleContact, TheGripperLetsGoWhenAskedForNoForceAndGraspsAgain) {
  // A grasp force of zero: each finger backs off until its skin presses on the ball with
  // none (the barrier's force fades at the edge of its range, dhat), then grasps again.
  const Json s = run(kSource + "/input/gripper_grasp.yaml", "gripper_let_go",
                     {"control.targets=[{grip_left: [0, -0.04, 0], grip_right: [0, 0.04, 0]}, "
                      "{grip_left: [0, 0, 0], grip_right: [0, 0, 0]}, "
                      "{grip_left: [0, -0.04, 0], grip_right: [0, 0.04, 0]}]"});
  const auto& answers = s["targets"];
  ASSERT_EQ(answers.size(), 6u);
  for (const auto& t : answers) EXPECT_NEAR(grasp(t), t["target"][1].get<double>(), 1e-6);
  for (int finger = 0; finger < 2; ++finger) {
    // Let go: less pressure than the grasp, and the same grasp again after it.
    const double grasping = answers[finger]["actuation"][finger].get<double>();
    EXPECT_LT(answers[2 + finger]["actuation"][finger].get<double>(), 0.5 * grasping);
    EXPECT_NEAR(answers[4 + finger]["actuation"][finger].get<double>(), grasping, 1e-3 * grasping);
  }
  // Let go, the ball carries less than a micronewton.
  const auto& released = answers[2]["contact"]["obstacles"][0]["force_N"];
  for (int d = 0; d < 3; ++d) EXPECT_LT(std::abs(released[d].get<double>()), 1e-6) << d;
}

TEST(ObstacleContact, TheQpWithContactForcesGraspsTheBallTouchingIt) {
  // input/gripper_grasp.yaml with control.contact_forces qp: the ball's normal forces on the
  // skin's nodes are unknowns of the QP beside the pressures, under complementarity, and the
  // free configurations hold them as loads (no barrier). Each finger presses with the force
  // asked for; at every answer the linearised gaps and forces are complementary, and the
  // nodes that carry a force touch the ball (no standoff of the barrier's reach, 0.1 mm); the
  // held forces are loads like any other, so the palm, the weight and the ball balance.
  const std::string folder = (hs_test::test_folder() / "gripper_qp").string();
  const Json s =
      run(kSource + "/input/gripper_grasp.yaml", "gripper_qp", {"control.contact_forces=qp"});
  const auto& answers = s["targets"];
  ASSERT_EQ(answers.size(), 6u);
  for (const auto& t : answers) {
    EXPECT_NEAR(grasp(t), t["target"][1].get<double>(), 1e-6) << t.dump();
    const auto& qp = t["contact_qp"];
    EXPECT_FALSE(qp["cycled"].get<bool>());
    EXPECT_GT(qp["touching"].get<int>(), 0);
    EXPECT_LT(qp["complementarity_Nm"].get<double>(), 1e-15);
    EXPECT_GE(qp["least_gap_m"].get<double>(), -1e-12);
    EXPECT_GE(qp["least_force_N"].get<double>(), 0.0);
    EXPECT_LT(t["contact"]["loaded_gap_m"].get<double>(), 1e-6);
    EXPECT_GT(t["contact"]["min_gap_m"].get<double>(), -1e-6);
  }
  const auto ball = obstacle_force(s, 0);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(answers[4]["reached"][d].get<double>() + answers[5]["reached"][d].get<double>(),
                ball[d], 1e-12)
        << d;
  const auto& base = s["reactions_N"]["base"];
  const auto load = total_load(folder + "/gripper_grasp.h5", answers[5]["step"].get<int>());
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(base[d].get<double>() + load[d] - ball[d], 0, 1e-7 * std::abs(load[0])) << d;
}

TEST(ObstacleContact, TheQpWithContactForcesLiftsTheFingerOffTheBallAndLandsItAgain) {
  // A finger resting on a ball under its weight (the barrier's contact until control begins,
  // then held forces), its tip steered up off the ball and down onto it again: contact opens
  // and closes inside the QP's active sets, every target is met, the ball carries the finger
  // where it touches and nothing where it was let go.
  const std::string deck =
      write_deck("qp_open_close.yaml",
                 finger_lifting_off_ball_deck("  steps_per_target: 6\n  contact_forces: qp\n"));
  const Json s = run(deck, "qp_open_close");
  const auto& answers = s["targets"];
  ASSERT_EQ(answers.size(), 4u);
  for (const auto& t : answers) {
    EXPECT_NEAR(t["reached"][2].get<double>(), t["target"][2].get<double>(), 1e-6) << t.dump();
    EXPECT_LT(t["contact_qp"]["complementarity_Nm"].get<double>(), 1e-15);
  }
  auto pressing = [&](int k) {
    return answers[k]["contact"]["obstacles"][0]["force_N"][2].get<double>() < 0;
  };
  EXPECT_TRUE(pressing(0));
  EXPECT_FALSE(pressing(2));
  EXPECT_TRUE(pressing(3));
  EXPECT_EQ(answers[2]["contact_qp"]["touching"].get<int>(), 0);
  EXPECT_LT(answers[3]["contact"]["loaded_gap_m"].get<double>(), 1e-6);
}

TEST(ObstacleContact, TheRealTimeGripperAnswersWithEquilibria) {
  // The same gripper in the real-time step, one step a target: closing on the ball (the
  // first line) its correction's free step meets the ball and the answer is the equilibrium
  // at its pressures, converged by Newton; in contact, refined from the correction (the chord
  // step's end had 5-49 negative pivots on this body), each answer is the equilibrium that
  // presses with the force asked for (from the third line on: the second, 20 kPa further,
  // still met the ball).
  std::string targets;
  for (double f : {0.04, 0.06, 0.05, 0.07})
    targets += "    - {grip_left: [0, " + std::to_string(-f) + ", 0], grip_right: [0, " +
               std::to_string(f) + ", 0]}\n";
  std::ifstream shipped(kSource + "/input/gripper_grasp.yaml");
  std::stringstream text;
  text << shipped.rdbuf();
  std::string scene = text.str();
  scene = scene.substr(0, scene.find("\ncontrol:\n") + 1);
  scene.replace(scene.find("../meshes/"), 10, kSource + "/meshes/");
  const std::string deck = write_deck(
      "gripper_realtime.yaml",
      scene +
          "control:\n  effectors:\n"
          "    - {name: grip_left, obstacle: ball, surfaces: [skin_left], directions: [y]}\n"
          "    - {name: grip_right, obstacle: ball, surfaces: [skin_right], directions: [y]}\n"
          "  actuators:\n"
          "    - {cavity: cavity_left, min_pressure: 0, max_pressure: 40000}\n"
          "    - {cavity: cavity_right, min_pressure: 0, max_pressure: 40000}\n"
          "  targets:\n" +
          targets + "  steps_per_target: 1\n  free_solve: one_step\n  check_equilibrium: true\n");
  const Json s = run(deck, "gripper_realtime");
  const auto& answers = s["targets"];
  ASSERT_EQ(answers.size(), 8u);
  for (const auto& t : answers) {
    EXPECT_NEAR(grasp(t), t["equilibrium"][1].get<double>(), 1e-6) << t.dump();
    if (!t.contains("fallback"))  // refined: the force asked for
      EXPECT_NEAR(grasp(t), t["target"][1].get<double>(), 1e-5) << t.dump();
  }
  for (size_t k = 4; k < 8; ++k) EXPECT_FALSE(answers[k].contains("fallback")) << k;
}

TEST(ObstacleContact, ADroppedBlockLandsAndBackwardEulerTakesItsEnergy) {
  // A free block 2 mm above a floor falls, hits it and bounces (time steps of 2 ms, full
  // Newton steps shortened before any node reaches the floor). Backward Euler only dissipates:
  // the energy's largest departure from its start is its end, a loss between nothing and
  // twice the fall's m g h, and no node is ever inside the floor.
  const double m = 1000 * 0.1 * 0.1 * 0.1, g = 9.81, h = 0.002;
  const std::string deck = write_deck(
      "drop.yaml",
      block_deck("materials:\n"
                 "  - {group: body, model: neo_hookean, E: 1.0e5, nu: 0.3, density: 1000}\n"
                 "loads: {gravity: [0, 0, -9.81]}\n"
                 "obstacles:\n  - {name: floor, type: plane, point: [0, 0, -0.002]}\n"
                 "contact: {surfaces: [bottom]}\n"
                 "time: {type: dynamic, dt: 0.002, end_time: 0.1, integrator: "
                 "backward_euler}\n"
                 "output: {every: 5}\n"));
  const Json s = run(deck, "drop");
  const double final_energy = s["energy"]["final"], drift = s["energy"]["max_drift"];
  EXPECT_LT(final_energy, -0.5 * m * g * h);
  EXPECT_GT(final_energy, -2 * m * g * h);
  EXPECT_NEAR(drift, -final_energy, 1e-12);
  EXPECT_GT(s["contact"]["min_gap_m"].get<double>(), 0);
  EXPECT_LT(obstacle_force(s, 0)[2], 0);  // on the floor at the end
}

class PressedIntoABlock : public ::testing::TestWithParam<std::string> {};

TEST_P(PressedIntoABlock, TheClampBalancesTheObstacleAndNoNodeReachesIt) {
  // A block clamped at its bottom, an obstacle brought down 8 mm onto its top (it starts
  // 2 mm above it): the force on the obstacle is the clamp's reaction (the body's internal
  // forces sum to zero: the obstacle pushes it down as hard as the clamp holds it up), and
  // the barrier keeps every node outside.
  const std::string obstacle = GetParam();
  const std::string shape = obstacle.substr(6, obstacle.find(',') - 6);
  const std::string deck =
      write_deck("pressed_" + shape + ".yaml",
                 block_deck("materials:\n"
                            "  - {group: body, model: neo_hookean, E: 1.0e5, nu: 0.45}\n"
                            "boundary:\n"
                            "  - {group: bottom}\n"
                            "obstacles:\n"
                            "  - {name: press, " +
                            obstacle +
                            ", move: [0, 0, -0.008]}\n"
                            "contact: {surfaces: [top, sides]}\n"
                            "time: {type: static, steps: 8}\n"));
  const Json s = run(deck, "pressed_" + shape);
  const auto f = obstacle_force(s, 0);
  const auto& clamp = s["reactions_N"]["bottom"];
  EXPECT_GT(f[2], 0.5);  // the body pushes the obstacle up
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(f[d], clamp[d].get<double>(), 1e-8 * f[2]) << shape << " " << d;
  EXPECT_GT(s["contact"]["min_gap_m"].get<double>(), 0);
  EXPECT_GT(s["contact"]["obstacles"][0]["area_m2"].get<double>(), 0);
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, PressedIntoABlock,
    ::testing::Values("type: sphere, center: [0.05, 0.05, 0.132], radius: 0.03",
                      "type: cylinder, center: [0.05, 0.05, 0.122], radius: 0.02, axis: [1, 0, 0]",
                      "type: box, center: [0.05, 0.05, 0.112], size: [0.04, 0.04, 0.02]"),
    [](const ::testing::TestParamInfo<std::string>& info) {
      return info.param.substr(6, info.param.find(',') - 6);
    });

}  // namespace mpi_test_contact
}  // namespace
