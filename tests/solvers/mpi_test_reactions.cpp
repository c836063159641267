// Reactions of the boundary groups and the tip's displacement (docs/output.md): the clamp of a
// cantilever carries its weight; a clamped block under gravity, a follower pressure and a dead
// traction reacts with minus the whole applied load (a conservation law: the internal forces
// sum to zero); a cavity clamped at both ends pushes on its clamps with the blocked force of
// plane-strain elasticity (up to its end walls' give), equal and opposite at the two ends; a
// state that moves a boundary group changes its force as elasticity says.
// On 2 ranks every figure is compared with the same deck run on one (each node's force
// counted by its owner alone).
#include <gtest/gtest.h>
#include <mpi.h>

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../mpi_test_decks.hpp"
#include "deck/deck.hpp"
#include "solvers/simulation.hpp"

namespace {
namespace mpi_test_reactions {

using Json = nlohmann::json;
using hs_test::shared;
using hs_test::world_rank;
using hs_test::world_size;
using hs_test::write_deck;
using Force = std::array<double, 3>;

const std::string kSource = HYDROSOFT_SOURCE_DIR;
constexpr double kPi = 3.14159265358979323846;

struct Runs {
  Json all;            // on every rank of the world
  Json one;            // on rank 0 alone (null on 1 rank: the same run)
  std::string folder;  // the first run's output
};

// The deck on every rank, and on 2 ranks also on rank 0 alone.
Runs run_both(const std::string& deck, const std::string& tag) {
  Runs r;
  r.folder = (hs_test::test_folder() / tag).string();
  r.all = shared(
      hs::run_simulation(hs::parse_deck(deck, {"output.folder=" + r.folder}), MPI_COMM_WORLD));
  if (world_size() > 1) {
    const std::string alone = r.folder + "_one_rank";
    if (world_rank() == 0)
      r.one = hs::run_simulation(hs::parse_deck(deck, {"output.folder=" + alone}), MPI_COMM_SELF);
    r.one = shared(r.one);
  }
  return r;
}

Force force(const Json& reactions, const std::string& group) {
  const auto& f = reactions.at(group);
  return {f[0].get<double>(), f[1].get<double>(), f[2].get<double>()};
}

double magnitude(const Force& f) { return std::hypot(f[0], f[1], f[2]); }

// The same reactions to round-off on 1 and 2 ranks (the sums differ only in their order).
void expect_same_on_one_rank(const Runs& r, const std::string& group, double scale) {
  if (r.one.is_null()) return;
  const Force a = force(r.all["reactions_N"], group), b = force(r.one["reactions_N"], group);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(a[d], b[d], 1e-10 * scale) << group << " " << d;
}

// The last row of history.csv as {column: value}.
std::map<std::string, double> last_history_row(const std::string& folder) {
  std::ifstream in(folder + "/history.csv");
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::map<std::string, double> row;
  std::stringstream names(header), values(last);
  std::string name, value;
  while (std::getline(names, name, ',') && std::getline(values, value, ','))
    row[name] = std::stod(value);
  return row;
}

// The sum over the nodes of the last step's nodal_load in the .h5.
Force total_applied_load(const std::string& h5_path, int step) {
  Force total{0, 0, 0};
  const std::vector<double> load =
      hs_test::read_dataset(h5_path, "/step_" + std::to_string(step) + "/nodal_load");
  for (size_t i = 0; i < load.size(); ++i) total[i % 3] += load[i];
  return total;
}

TEST(Reactions, TheClampOfACantileverCarriesItsWeight) {
  // 1 m x 50 mm x 50 mm of steel-like density 1000 kg/m^3 under g = 9.81 m/s^2 along -z:
  // the clamp pushes up with rho g L h^2 = 24.525 N. The tip's centroid sinks by the
  // Euler-Bernoulli deflection 3 rho g L^4 / (2 E h^2) (shear adds 0.26 %, the P2 mesh of
  // two elements through the depth is within 1 % of the beam).
  const double rho = 1000, g = 9.81, L = 1.0, h = 0.05, E = 1e9;
  const std::string deck = write_deck("cantilever.yaml", "mesh:\n  file: " + kSource +
                                                             "/meshes/cantilever.geo\n"
                                                             "  order: 2\n"
                                                             "  parameters: {L: 1.0, h: 0.05}\n"
                                                             "materials:\n"
                                                             "  - {group: body, model: "
                                                             "linear_elastic, E: 1.0e9, nu: 0.3, "
                                                             "density: 1000}\n"
                                                             "boundary:\n  - {group: clamped}\n"
                                                             "loads:\n  gravity: [0, 0, -9.81]\n"
                                                             "tip: {group: tip}\n"
                                                             "solver: {preset: mumps}\n");
  const Runs r = run_both(deck, "cantilever");
  const double weight = rho * g * L * h * h;
  const Force reaction = force(r.all["reactions_N"], "clamped");
  EXPECT_NEAR(reaction[2], weight, 1e-9 * weight);
  EXPECT_NEAR(reaction[0], 0, 1e-9 * weight);
  EXPECT_NEAR(reaction[1], 0, 1e-9 * weight);
  expect_same_on_one_rank(r, "clamped", weight);
  // The state's reactions and the history's last row are the same figures.
  const Json& state = r.all["states"].back();
  EXPECT_EQ(force(state["reactions_N"], "clamped"), reaction);
  if (world_rank() == 0) {
    const auto row = last_history_row(r.folder);
    ASSERT_TRUE(row.count("reaction_clamped_z_N"));
    EXPECT_NEAR(row.at("reaction_clamped_z_N"), weight, 1e-9 * weight);
    EXPECT_NEAR(row.at("reaction_clamped_x_N"), 0, 1e-9 * weight);
  }
  // The tip's centroid displacement: down by the beam's deflection, not along or across.
  const Json& tip = state["tip"];
  const double deflection = 3 * rho * g * std::pow(L, 4) / (2 * E * h * h);
  const auto& d = tip["displacement_m"];
  EXPECT_NEAR(-d[2].get<double>(), deflection, 0.01 * deflection);
  // Across: zero on a symmetric mesh; the unstructured one leaves 5e-5 of the deflection.
  EXPECT_LT(std::abs(d[1].get<double>()), 1e-3 * deflection);
  EXPECT_NEAR(tip["displacement_magnitude_m"].get<double>(),
              std::hypot(d[0].get<double>(), d[1].get<double>(), d[2].get<double>()), 1e-15);
}

TEST(Reactions, ABlockReactsWithMinusTheWholeAppliedLoad) {
  // A neo-Hookean block clamped at its bottom and held in x on its side x0 (the two share an
  // edge), under gravity (tilted), a follower pressure on its top and a dead traction on its
  // side x1 that pushes it against x0, deformed by several percent: the internal forces of
  // every element sum to zero, so at equilibrium the two groups' forces add up to minus the
  // sum of every applied nodal load, the deformed pressure's included; the shared edge's
  // x-forces count once (in bottom, the first group).
  const std::string deck = write_deck(
      "block.yaml", "mesh:\n  file: " + kSource +
                        "/meshes/block.geo\n"
                        "  order: 1\n"
                        "  parameters: {H: 0.1, h: 0.05}\n"
                        "materials:\n"
                        "  - {group: body, model: neo_hookean, E: 1.0e5, nu: 0.3, density: 1000}\n"
                        "boundary:\n  - {group: bottom}\n  - {group: x0, components: [x]}\n"
                        "loads:\n  gravity: [2.0, 0, -9.81]\n"
                        "  pressure:\n    - {group: top, value: 3000}\n"
                        "  traction:\n    - {group: x1, value: [-2000, 2000, 1000]}\n"
                        "time: {type: static, steps: 2}\n"
                        "solver: {preset: mumps}\n");
  const Runs r = run_both(deck, "block");
  const Force bottom = force(r.all["reactions_N"], "bottom");
  const Force side = force(r.all["reactions_N"], "x0");
  // Dead parts alone, for the scale: 3000 Pa x 0.01 m^2 = 30 N on the top.
  const double scale = 30;
  if (world_rank() == 0) {
    const Force load = total_applied_load(r.folder + "/block.h5", 1);
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(bottom[d] + side[d], -load[d], 1e-8 * scale) << d;
    // Closed form of the dead parts: the traction's force on x1 is exact; the pressure's
    // follows the top face, so only its order of size is known.
    EXPECT_NEAR(load[1], 2000 * 0.01, 0.05 * scale);
    const auto row = last_history_row(r.folder);
    EXPECT_NEAR(row.at("reaction_bottom_y_N"), bottom[1], 1e-9 * scale);
    EXPECT_NEAR(row.at("reaction_x0_x_N"), side[0], 1e-9 * scale);
  }
  // x0 holds x alone, and pushes back against the traction's 20 N.
  EXPECT_EQ(side[1], 0);
  EXPECT_EQ(side[2], 0);
  EXPECT_GT(side[0], 0.1 * 20);
  EXPECT_GT(magnitude(bottom), scale);
  expect_same_on_one_rank(r, "bottom", scale);
  expect_same_on_one_rank(r, "x0", scale);
}

TEST(Reactions, AStateMovesABoundaryGroupByItsTranslation) {
  // A linear elastic block (nu = 0: uniaxial stress, exact on any mesh) on symmetry planes, its
  // top pressed 2 mm down over the first state, then moved 5 mm up (a state's `move`; its x
  // part falls on no prescribed component) and held over a third: the top's force is
  // E A delta / H with delta -2, then +3 mm, kept.
  const double E = 1e5, A = 0.01, H = 0.1;
  const std::string deck = write_deck(
      "moved.yaml", "mesh:\n  file: " + kSource +
                        "/meshes/block.geo\n"
                        "  order: 1\n"
                        "  parameters: {H: 0.1, h: 0.05}\n"
                        "materials:\n"
                        "  - {group: body, model: linear_elastic, E: 1.0e5, nu: 0.0}\n"
                        "boundary:\n  - {group: bottom, components: [z]}\n"
                        "  - {group: x0, components: [x]}\n  - {group: y0, components: [y]}\n"
                        "  - {group: top, components: [z], value: [0, 0, -0.002]}\n"
                        "states:\n  - {name: press, steps: 2}\n"
                        "  - {name: pull, steps: 3, move: {top: [0.01, 0, 0.005]}}\n"
                        "  - {name: hold}\n"
                        "solver: {preset: mumps}\n");
  const Runs r = run_both(deck, "moved");
  const Json& states = r.all["states"];
  ASSERT_EQ(states.size(), 3u);
  const double delta[3] = {-0.002, 0.003, 0.003};
  for (int k = 0; k < 3; ++k) {
    const Force top = force(states[k]["reactions_N"], "top");
    EXPECT_NEAR(top[2], E * A * delta[k] / H, 1e-9 * E * A * 0.002 / H) << k;
    EXPECT_EQ(top[0], 0) << k;
  }
  expect_same_on_one_rank(r, "top", E * A * 0.003 / H);
}

TEST(Reactions, BlockedForceOfACavityClampedAtBothEnds) {
  // The cylinder of input/cylinder_air.yaml (coaxial cavity, no gravity) with both end faces
  // clamped, its cavity at a gauge pressure p. Away from the ends it is in plane strain,
  // eps_z = 0, so sigma_z = nu (sigma_r + sigma_theta), whose integral over the wall is
  // 2 nu p A (A the cavity's section, for any wall). A free body from a clamp to the middle:
  // the clamp holds the end wall's p A against the wall's 2 nu p A, so each clamp pushes
  // with (1 - 2 nu) p A inwards along the axis, equal and opposite at the two ends (a
  // closed cavity's pressure has no net force). That is the limit of a long tube at small
  // strain: the end walls give under the pressure on them, which compresses the tube
  // (eps_z < 0), and the pressure acts on the inflated section, both adding to the force:
  // 11.4 % more here (11.7 % on a mesh of h = 6 mm), 7.0 % for a tube twice as long.
  const double p = 500, nu = 0.3, L = 0.15, t = 0.006;
  const std::string deck = write_deck(
      "blocked.yaml", "mesh:\n  file: " + kSource +
                          "/meshes/cylinder.geo\n"
                          "  order: 2\n"
                          "  parameters: {R: 0.02, L: 0.15, t: 0.006, e: 0, h: 0.011}\n"
                          "materials:\n"
                          "  - {group: body, model: neo_hookean, E: 2.0e5, nu: 0.3, "
                          "density: 1070}\n"
                          "boundary:\n  - {group: top}\n  - {group: tip}\n"
                          "cavities:\n  - {group: cavity, kind: pneumatic}\n"
                          "states:\n  - {name: rest, steps: 1}\n"
                          "  - {name: blocked, steps: 2, cavities: {cavity: {pressure: 500}}}\n"
                          "solver: {preset: mumps}\n");
  const Runs r = run_both(deck, "blocked");
  const Json& states = r.all["states"];
  ASSERT_EQ(states.size(), 2u);
  // The section of the meshed cavity: its volume at rest over its length.
  const double section = states[0]["cavities"][0]["volume_ml"].get<double>() * 1e-6 / (L - 2 * t);
  EXPECT_NEAR(section, kPi * 0.014 * 0.014, 0.05 * kPi * 0.014 * 0.014);
  const double blocked = (1 - 2 * nu) * p * section;
  const Force top = force(states[1]["reactions_N"], "top");
  const Force tip = force(states[1]["reactions_N"], "tip");
  // The top face is z = 0, the body below it: the clamp there pulls the body down (-z).
  EXPECT_GT(-top[2], blocked);
  EXPECT_LT(-top[2], 1.15 * blocked);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(top[d] + tip[d], 0, 1e-9 * p * section) << d;
  EXPECT_LT(std::hypot(top[0], top[1]), 1e-3 * blocked);  // along the axis
  // At rest nothing pushes.
  EXPECT_LT(magnitude(force(states[0]["reactions_N"], "top")), 1e-9 * p * section);
  expect_same_on_one_rank(r, "top", p * section);
  expect_same_on_one_rank(r, "tip", p * section);
}

}  // namespace mpi_test_reactions
}  // namespace
