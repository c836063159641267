// Reduced-order models (docs/reduced_models.md) on one rank: with the full basis and every
// element the reduced equations are the full model's, so their solution is the full model's
// to solver accuracy; a trained model answers targets within its stated error of the full
// model's equilibrium; a model is refused by a run it does not belong to.
#include <gtest/gtest.h>

#include <cmath>

#include "../pinned_decks.hpp"
#include "common/error.hpp"
#include "control_scene.hpp"
#include "run_deck.hpp"
#include "solvers/reduced/error_indicator.hpp"
#include "solvers/reduced/model_fit.hpp"
#include "solvers/reduced/reduced_system.hpp"

namespace {

using hs_test::out_folder;

const char* kDeck = "finger_pneumatic.yaml";

hs::ActuatorConfig cavity_actuator() {
  hs::ActuatorConfig a;
  a.constraint = "cavity";
  a.min_multiplier = 0;
  a.max_multiplier = 30000;
  return a;
}

double norm_of(Vec v) {
  PetscReal n = 0;
  VecNorm(v, NORM_2, &n);
  return n;
}

// A model's record of the scene's mesh, physics and one actuator (0-30 kPa), without a basis.
hs::ReducedModel reduced_model_of(const hs_test::ControlScene& scene) {
  hs::ReducedModel model;
  hs::record_mesh(*scene.problem, model);
  model.physics = hs::reduced_physics(scene.config);
  model.actuators = {"cavity"};
  model.lower = {0};
  model.upper = {30000};
  return model;
}

// With the full basis and every element (and, in a nodal-pressure body, every node's patch
// term) weighing 1, the reduced equations are the full model's: the reduced Newton finds the
// full model's equilibrium at 20 kPa, and the full model's solution already balances them.
void expect_the_full_basis_solves_the_full_model(const std::vector<std::string>& overrides,
                                                 double from = 0) {
  hs_test::ControlScene scene(kDeck, {0.085, 0.0, 0.0}, cavity_actuator(),
                              hs_test::compressible_finger(overrides));
  hs::Problem& problem = *scene.problem;
  const hs::Distribution& dist = problem.distribution();
  hs::ReducedModel model = reduced_model_of(scene);
  // The basis: one unit column per free dof (in mesh numbering).
  std::vector<int64_t> free_dofs;
  for (int64_t n = 0; n < dist.num_local(); ++n)
    for (int d = 0; d < 3; ++d)
      if (!problem.constrained(3 * n + d)) free_dofs.push_back(3 * dist.old_of_local[n] + d);
  const int k = static_cast<int>(free_dofs.size());
  model.basis = Eigen::MatrixXd::Zero(3 * model.nodes, k);
  for (int j = 0; j < k; ++j) model.basis(free_dofs[j], j) = 1;
  model.elements = dist.local_tets;
  model.weights.assign(model.elements.size(), 1.0);
  if (const hs::NodalPressure* nodal = problem.nodal_pressure()) {
    const auto around = nodal->patch_elements();
    for (int64_t n = 0; n < dist.num_local(); ++n)
      if (!around[n].empty()) model.patches.push_back(dist.old_of_local[n]);
    model.patch_weights.assign(model.patches.size(), 1.0);
  }
  model.training_actuations = Eigen::MatrixXd::Zero(1, 1);
  model.training_states = Eigen::MatrixXd::Zero(1, k);
  model.report = {{"held_back", {{"max_effector_error_m", 0.0}}}};
  hs::ReducedSystem reduced(scene.config, problem, *scene.cavities, model, "full basis", {});
  EXPECT_EQ(reduced.size(), k);

  const double p = 20000;
  const hs::VecHandle full(problem.create_vector());
  VecCopy(scene.rest, full);
  for (int i = 1; i <= 4; ++i) scene.solve_at(full, p * i / 4);
  const hs::VecHandle u(problem.create_vector());
  (*scene.cavities)[0].prescribe(hs::Constraint::Control::multiplier, p);
  // From rest, or from `from` times the full model's solution: a nearly
  // incompressible body's Newton converges slowly from afar, and each of its iterations
  // with the full basis costs seconds.
  VecCopy(scene.rest, u);
  if (from > 0) VecAXPBY(u, from, 0.0, full);
  Eigen::VectorXd q = reduced.project(u);
  const hs::ReducedSolve solved = reduced.solve(q, u);
  ASSERT_TRUE(solved.converged) << solved.reason;
  reduced.place(q, u, true);
  const hs::VecHandle diff(problem.create_vector());
  VecWAXPY(diff, -1.0, full, u);
  // Both Newton solves stop at ~1e-10 of the forces; the finger's stiffness turns that into
  // ~1e-9 of its displacement.
  EXPECT_LT(norm_of(diff), 1e-8 * norm_of(full)) << norm_of(diff) << " of " << norm_of(full);
  // The full model's solution already balances the reduced equations.
  q = reduced.project(full);
  const hs::ReducedSolve at_full = reduced.solve(q, u);
  EXPECT_TRUE(at_full.converged);
  EXPECT_LE(at_full.iterations, 1);
}

TEST(ReducedSystem, WithTheFullBasisAndEveryElementSolvesTheFullModel) {
  expect_the_full_basis_solves_the_full_model({"mesh.parameters.h=0.01"});
}

// Silicone at nu 0.4995 on P1 runs the nodal-pressure element: its volumetric term is
// sampled per node patch (NodalPressure::patch_term), apart from the elements' rest.
TEST(ReducedSystem, WithTheFullBasisEveryElementAndEveryPatchSolvesANodalPressureBody) {
  expect_the_full_basis_solves_the_full_model({"mesh.parameters.h=0.01", "materials[0].nu=0.4995"},
                                              0.9);
}

// The error indicator (solvers/reduced/error_indicator.hpp) at a training sample's own state
// uses the exact tangent there: for a state displaced from that equilibrium by eps times its
// own displacement, the indicator is the Newton step back, -eps times the effector's
// displacement, to second order in eps; at the equilibrium itself, nothing.
TEST(ReducedSystem, ResidualIndicatorIsTheNewtonStepBackToEquilibrium) {
  hs_test::ControlScene scene(kDeck, {0.085, 0.0, 0.0}, cavity_actuator(),
                              hs_test::compressible_finger({"mesh.parameters.h=0.01"}));
  hs::Problem& problem = *scene.problem;
  const hs::Distribution& dist = problem.distribution();
  const double p = 20000;
  const hs::VecHandle full(problem.create_vector());
  VecCopy(scene.rest, full);
  for (int i = 1; i <= 4; ++i) scene.solve_at(full, p * i / 4);
  hs::ReducedModel model = reduced_model_of(scene);
  // One mode, the equilibrium itself (mesh numbering), normalized; its one training sample.
  const PetscScalar* a = nullptr;
  VecGetArrayRead(full, &a);
  model.basis = Eigen::MatrixXd::Zero(3 * model.nodes, 1);
  for (int64_t n = 0; n < dist.num_local(); ++n)
    for (int d = 0; d < 3; ++d) model.basis(3 * dist.old_of_local[n] + d, 0) = a[3 * n + d];
  VecRestoreArrayRead(full, &a);
  const double length = model.basis.norm();
  model.basis /= length;
  model.elements = dist.local_tets;
  model.weights.assign(model.elements.size(), 1.0);
  model.training_actuations = Eigen::MatrixXd::Constant(1, 1, p);
  model.training_states = Eigen::MatrixXd::Constant(1, 1, length);
  model.report = {{"held_back", {{"max_effector_error_m", 0.0}}}};
  std::vector<Vec> rows;
  for (int d = 0; d < 3; ++d) rows.push_back(scene.effectors->row(0, d));
  hs::ReducedSystem reduced(scene.config, problem, *scene.cavities, model, "one mode", rows);
  (*scene.cavities)[0].prescribe(hs::Constraint::Control::multiplier, p);
  hs::ResidualErrorIndicator indicator(problem, *scene.cavities, reduced, {0}, rows);

  Eigen::Vector3d moved;  // the effector's displacement at the equilibrium
  for (int d = 0; d < 3; ++d) VecDot(rows[d], full, &moved(d));
  const Eigen::VectorXd lambda = Eigen::VectorXd::Constant(1, p);
  const hs::VecHandle u(problem.create_vector());
  Eigen::VectorXd dx;
  VecCopy(full, u);
  ASSERT_TRUE(indicator.estimate(u, lambda, dx));
  EXPECT_LT(dx.norm(), 1e-7 * moved.norm()) << dx.transpose();  // Newton's own tolerance
  std::vector<double> misses;                                   // |dx + eps moved| at eps and 2 eps
  for (double eps : {1e-3, 2e-3}) {
    VecCopy(full, u);
    VecScale(u, 1 + eps);
    ASSERT_TRUE(indicator.estimate(u, lambda, dx));
    misses.push_back((dx + eps * moved).norm());
    // The first-order term: within a few eps of the step itself (3.4 eps measured).
    EXPECT_LT(misses.back(), 10 * eps * eps * moved.norm())
        << eps << ": " << dx.transpose() << " against " << -eps * moved.transpose();
    EXPECT_NEAR(hs::ResidualErrorIndicator::largest_move(dx), eps * moved.norm(),
                10 * eps * eps * moved.norm());
  }
  // What it misses is of second order: four times as much at twice the displacement.
  EXPECT_NEAR(misses[1] / misses[0], 4.0, 0.2);
}

// Trains `config`'s reduced model into `model` on `samples` samples; the training's report
// (summary.json's `reduction`).
nlohmann::json training_report(hs::Config config, const std::string& model, int samples,
                               hs::TrainingDesignKind design = hs::TrainingDesignKind::grid) {
  hs::TrainingConfig training;
  training.output = model;
  training.samples = samples;
  training.design = design;
  config.training = training;
  return hs::run_simulation(config, MPI_COMM_SELF).at("reduction");
}

// The held-back samples' largest effector error (NaN unless every one was solved).
double held_back_error(const nlohmann::json& report) {
  const nlohmann::json& held = report.at("held_back");
  EXPECT_EQ(held.at("unsolved"), 0) << held.dump();
  const nlohmann::json& e = held.at("max_effector_error_m");
  EXPECT_TRUE(e.is_number()) << held.dump();
  return e.is_number() ? e.get<double>() : std::nan("");
}

// Trains the pneumatic finger's model (9 samples of 0-30 kPa, 364 nodes) and answers the
// deck's own targets with it, each checked against the full model's equilibrium.
class TrainedModel : public ::testing::Test {
 protected:
  static hs::Config deck(const std::vector<std::string>& given, const std::string& tag) {
    // The compressible finger, the test's overrides may change it
    std::vector<std::string> overrides = hs_test::compressible_finger({"mesh.parameters.h=0.006"});
    overrides.insert(overrides.end(), given.begin(), given.end());
    overrides.push_back("output.progress=false");
    overrides.push_back("output.folder=" + out_folder(tag));
    return hs::parse_deck(std::string(HYDROSOFT_SOURCE_DIR) + "/input/" + kDeck, overrides);
  }
  static nlohmann::json train(const std::string& model,
                              hs::TrainingDesignKind design = hs::TrainingDesignKind::grid) {
    return {{"reduction", training_report(deck({}, "train"), model, 9, design)}};
  }
};

// A softer hydraulic finger (E 100 kPa, nu 0.4) trained up to 15 kPa, where the full Newton
// too needs 25 iterations: from its nearest training sample the reduced Newton stalls at the
// held-back 13.1 kPa (8 % of the forces left after 25 iterations), and is solved there by
// stepping the actuation from the sample's. Every held-back sample solved, the error stated.
TEST(ReducedModel, ASoftFingerNearItsLimitPointIsTrainedAndDriven) {
  hs::Config config =
      hs::parse_deck(std::string(HYDROSOFT_SOURCE_DIR) + "/input/finger_hydraulic.yaml",
                     {"mesh.parameters.h=0.004", "materials[0].E=1e5", "materials[0].nu=0.4",
                      "control.actuators[0].max_pressure=15000", "output.progress=false",
                      "output.folder=" + out_folder("soft")});
  const nlohmann::json report = training_report(config, out_folder("soft.h5"), 9);
  EXPECT_EQ(report.at("held_back").at("samples"), 4);
  const double stated = held_back_error(report);
  EXPECT_LT(stated, 5e-5);  // 0.013 mm measured

  // From 15 kPa (the first target is out of reach above) to a tip height the full model
  // meets at 13.6 kPa: the step's iterations, on linearizations left loose near the limit
  // point, cycled between 7.8 and 15 kPa and ended 1.3 mm short; now the target is met.
  hs::Config use = config;
  use.training.reset();
  use.control->reduced_model = out_folder("soft.h5");
  use.control->check_equilibrium = true;
  use.control->targets = {{{"tip", {0.09, 0, -0.01011}}}, {{"tip", {0.09, 0, -0.02377}}}};
  const nlohmann::json run = hs::run_simulation(use, MPI_COMM_SELF);
  const nlohmann::json& t = run.at("targets").at(1);
  EXPECT_FALSE(t.at("saturated")[0].get<bool>());
  EXPECT_LT(t.at("error_m").get<double>(), 1e-5) << t.dump();
  double d2 = 0;
  for (int i = 0; i < 3; ++i)
    d2 += std::pow(t["reached"][i].get<double>() - t["equilibrium"][i].get<double>(), 2);
  // 1.5 times the stated error measured here: the held-back sample at 13.1 kPa does not see
  // the larger error nearer 15 kPa.
  EXPECT_LT(std::sqrt(d2), 2 * stated);
}

// Silicone as cast (nu 0.4995: the nodal-pressure element) trained and driven: ECSW samples
// node patches beside elements, and every answer lies within the stated error of the full
// model's equilibrium at its pressure.
TEST_F(TrainedModel, ASiliconeFingerSamplesPatchesAndAnswersWithinItsStatedError) {
  const std::string model = out_folder("silicone.h5");
  const std::vector<std::string> silicone = {"materials[0].E=2.6e5", "materials[0].nu=0.4995"};
  const nlohmann::json r = training_report(deck(silicone, "silicone_train"), model, 9);
  const double stated = held_back_error(r);
  EXPECT_LT(stated, 5e-4);
  const nlohmann::json& ecsw = r.at("ecsw");
  EXPECT_GT(ecsw.at("patches").get<int>(), 0) << ecsw.dump();
  EXPECT_LT(ecsw.at("patches").get<int>(), ecsw.at("of_patches").get<int>() / 4) << ecsw.dump();

  std::vector<std::string> use = silicone;
  use.push_back("control.reduced_model=" + model);
  use.push_back("control.check_equilibrium=true");
  const nlohmann::json run = hs::run_simulation(deck(use, "silicone_use"), MPI_COMM_SELF);
  ASSERT_EQ(run.at("targets").size(), 6u);
  EXPECT_GT(run.at("reduced_model").at("patches").get<int>(), 0);
  int met = 0;
  for (const auto& t : run.at("targets")) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i)
      d2 += std::pow(t["reached"][i].get<double>() - t["equilibrium"][i].get<double>(), 2);
    EXPECT_LE(std::sqrt(d2), 1.5 * stated) << t.dump();
    if (!t.at("saturated")[0].get<bool>()) {
      EXPECT_LT(t.at("error_m").get<double>(), 1e-6) << t.dump();
      ++met;
    }
  }
  // The stiffer silicone's tip moves between -8.4 mm (rest) and -5.6 mm (30 kPa) on this
  // mesh: one of the deck's targets lies inside, met at 9.0 kPa, as by the full model.
  EXPECT_GE(met, 1);
}

// The hydraulic finger in silicone (nu 0.4995) near the top of its range, where the
// equilibrium at a fixed pressure is nearly singular: from 30 kPa (the first target is out of
// reach above) down to tip heights met at 28.5, 24.9 and 26.5 kPa. Each step used to solve
// its far landings to equilibrium, 10-16 reduced Newton iterations a line of steps of 1/32;
// with the halved steps going on as loose iterations, 4-5. A step to the bound takes the
// training sample there; one back up to it, 4 iterations.
TEST(ReducedModel, ASiliconeFingerNearTheTopOfItsRangeIsDrivenInAFewIterations) {
  const std::vector<std::string> silicone = {
      "mesh.parameters.h=0.006", "control.actuators[0].max_pressure=30000",
      "control.steps_per_target=1", "control.actuators[0].max_pressure_change=1e9",
      "output.progress=false"};
  auto deck = [&](const std::string& tag) {
    std::vector<std::string> overrides = silicone;
    overrides.push_back("output.folder=" + out_folder(tag));
    return hs::parse_deck(std::string(HYDROSOFT_SOURCE_DIR) + "/input/finger_hydraulic.yaml",
                          overrides);
  };
  const std::string model = out_folder("silicone_top.h5");
  const double stated = held_back_error(training_report(deck("silicone_top_train"), model, 9));
  EXPECT_LT(stated, 5e-5);

  hs::Config use = deck("silicone_top_use");
  use.control->reduced_model = model;
  use.control->check_equilibrium = true;
  use.control->targets.clear();
  for (double z : {0.0, -0.0075, 0.0, -0.0080, -0.0078})
    use.control->targets.push_back({{"tip", {0.09, 0, z}}});
  const nlohmann::json run = hs::run_simulation(use, MPI_COMM_SELF);
  ASSERT_EQ(run.at("targets").size(), 5u);
  for (const auto& t : run.at("targets")) {
    const bool saturated = t.at("saturated")[0].get<bool>();
    EXPECT_EQ(saturated, t.at("target")[2].get<double>() == 0.0) << t.dump();
    EXPECT_LE(t.at("reduced").at("newton_iterations").get<int>(), saturated ? 4 : 6) << t.dump();
    if (!saturated) EXPECT_LT(t.at("error_m").get<double>(), 1e-6) << t.dump();
    double d2 = 0;
    for (int i = 0; i < 3; ++i)
      d2 += std::pow(t["reached"][i].get<double>() - t["equilibrium"][i].get<double>(), 2);
    EXPECT_LE(std::sqrt(d2), 2 * stated) << t.dump();
  }
}

// The cable finger (nu 0.45): a straight cable's inner points carry no force at rest, yet
// the cable's length reads them. Kept up to date (Constraint::mark_reads), every held-back
// tension is solved; left at rest, 5 of 8 were not (6 on the deck's mesh).
TEST(ReducedModel, ACableFingerKeepsItsCablesPointsUpToDate) {
  hs::Config config =
      hs::parse_deck(std::string(HYDROSOFT_SOURCE_DIR) + "/input/finger_cable.yaml",
                     {"mesh.parameters.h=0.004", "materials[0].nu=0.45", "output.progress=false",
                      "output.folder=" + out_folder("cable")});
  const nlohmann::json report = training_report(config, out_folder("cable.h5"), 17);
  EXPECT_EQ(report.at("held_back").at("samples"), 8);
  EXPECT_LT(held_back_error(report), 5e-5);
}

// The pneumatic finger resting under its weight on a ball (the barrier at every contact
// node of the reconstructed skin), its tip steered up off the ball and down onto it again:
// every held-back pressure solved, each answer within the stated error of the full model's
// equilibrium at its pressure, the contact open and closed as the full model's.
TEST(ReducedModel, AFingerOnABallIsTrainedAndLiftedOffAndOntoIt) {
  auto deck = [](std::vector<std::string> more, const std::string& tag) {
    std::vector<std::string> o = {
        "mesh.parameters.h=0.004",
        "obstacles=[{name: ball, type: sphere, center: [0.07, 0, -0.026], radius: 0.01}]",
        "contact={surfaces: [outer, tip]}",
        "control.targets=[{tip: [0.09, 0, -0.009]}, {tip: [0.09, 0, -0.002]}, "
        "{tip: [0.09, 0, -0.0015]}, {tip: [0.09, 0, -0.010]}]",
        "control.steps_per_target=1",
        "control.actuators[0].max_pressure_change=1e9",
        "output.progress=false",
        "output.folder=" + out_folder(tag)};
    o.insert(o.end(), more.begin(), more.end());
    return hs::parse_deck(std::string(HYDROSOFT_SOURCE_DIR) + "/input/" + kDeck,
                          hs_test::compressible_finger(o));
  };
  const std::string model = out_folder("ball.h5");
  const double stated = held_back_error(training_report(deck({}, "ball_train"), model, 17));
  EXPECT_LT(stated, 5e-4);

  const nlohmann::json run = hs::run_simulation(
      deck({"control.reduced_model=" + model, "control.check_equilibrium=true"}, "ball_use"),
      MPI_COMM_SELF);
  const auto& answers = run.at("targets");
  ASSERT_EQ(answers.size(), 4u);
  for (const auto& t : answers) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i)
      d2 += std::pow(t["reached"][i].get<double>() - t["equilibrium"][i].get<double>(), 2);
    EXPECT_LE(std::sqrt(d2), 1.5 * stated) << t.dump();
  }
  auto pressing = [&](int k) {
    return answers[k]["contact"]["obstacles"][0]["force_N"][2].get<double>() < 0;
  };
  EXPECT_TRUE(pressing(0));   // on the ball
  EXPECT_FALSE(pressing(2));  // lifted off it
  EXPECT_TRUE(pressing(3));   // landed on it again
}

TEST_F(TrainedModel, AnswersWithinItsStatedErrorAndTrainsOnlyForItsOwnRun) {
  const std::string model = out_folder("finger.h5");
  const nlohmann::json trained = train(model);
  const nlohmann::json& r = trained.at("reduction");
  EXPECT_EQ(r.at("samples"), 9);
  EXPECT_EQ(r.at("held_back").at("samples"), 4);  // the midpoints between training samples
  const double stated = r.at("held_back").at("max_effector_error_m");
  EXPECT_GT(stated, 0);
  EXPECT_LT(stated, 5e-4);
  EXPECT_GT(r.at("held_back").at("indicator_ratio_max").get<double>(), 0);
  EXPECT_LT(r.at("ecsw").at("elements").get<int>(), r.at("ecsw").at("of").get<int>() / 20);

  const nlohmann::json run =
      hs::run_simulation(deck({"control.reduced_model=" + model, "control.check_equilibrium=true",
                               "control.error_indicator=true"},
                              "use"),
                         MPI_COMM_SELF);
  ASSERT_EQ(run.at("targets").size(), 6u);
  int met = 0;  // targets inside the finger's reach
  for (const auto& t : run.at("targets")) {
    double d2 = 0;
    for (int i = 0; i < 3; ++i)
      d2 += std::pow(t["reached"][i].get<double>() - t["equilibrium"][i].get<double>(), 2);
    // The held-back samples' largest error, with the margin of a sample of four.
    EXPECT_LE(std::sqrt(d2), 1.5 * stated) << t.dump();
    // With the residual indicator the stated error bounds it (docs/reduced_models.md).
    EXPECT_LE(std::sqrt(d2), t.at("reduced").at("estimated_error_m").get<double>()) << t.dump();
    EXPECT_TRUE(t.at("reduced").at("in_envelope"));
    // The larger of the held-back error and the residual indicator, calibrated by the
    // held-back samples' largest ratio (at least 1).
    const nlohmann::json& said = t.at("reduced");
    ASSERT_TRUE(said.at("indicator_m").is_number()) << said.dump();
    EXPECT_GE(said.at("estimated_error_m").get<double>(), said.at("indicator_m").get<double>());
    EXPECT_GE(said.at("estimated_error_m").get<double>(), stated);
    EXPECT_EQ(said.at("held_back_error_m"), stated);
    // A target inside the finger's reach (its pressure within the bounds) is met.
    if (!t.at("saturated")[0].get<bool>()) {
      EXPECT_LT(t.at("error_m").get<double>(), 1e-6);
      ++met;
    }
  }
  EXPECT_GE(met, 2);
  EXPECT_EQ(run.at("reduced_model").at("modes"), r.at("pod").at("modes"));

  // The full-model check on the first set and every 4th after it: the same equilibria there,
  // none elsewhere.
  const nlohmann::json sampled =
      hs::run_simulation(deck({"control.reduced_model=" + model, "control.check_equilibrium=true",
                               "control.check_every=4"},
                              "every4"),
                         MPI_COMM_SELF);
  for (size_t i = 0; i < 6; ++i) {
    const nlohmann::json& t = sampled.at("targets")[i];
    // Ten steps a set: the answer waits for all of them, not the last alone.
    EXPECT_GE(t.at("answer_ms").get<double>(), t.at("step_ms").get<double>()) << i;
    EXPECT_EQ(t.contains("equilibrium"), i % 4 == 0) << i;
    if (t.contains("equilibrium")) EXPECT_EQ(t["equilibrium"], run["targets"][i]["equilibrium"]);
  }

  // Without a per-step pressure limit each target is one step, most of them far from the
  // last equilibrium: the same answers, to the stopping rule's 10 um.
  const nlohmann::json far =
      hs::run_simulation(deck({"control.reduced_model=" + model, "control.steps_per_target=1",
                               "control.actuators[0].max_pressure_change=1e9"},
                              "far"),
                         MPI_COMM_SELF);
  ASSERT_EQ(far.at("targets").size(), 6u);
  for (size_t i = 0; i < 6; ++i) {
    const nlohmann::json &a = far["targets"][i], &b = run["targets"][i];
    for (int d = 0; d < 3; ++d)
      EXPECT_NEAR(a["reached"][d].get<double>(), b["reached"][d].get<double>(), 1e-5) << i;
    if (!a.at("saturated")[0].get<bool>()) EXPECT_LT(a.at("error_m").get<double>(), 1e-5);
  }

  // The space-filling design (for many actuators; here one): the two ends and seven points of
  // the van der Corput sequence, the 4th held back, a model as accurate.
  const nlohmann::json halton =
      train(out_folder("halton.h5"), hs::TrainingDesignKind::halton).at("reduction");
  EXPECT_EQ(halton.at("samples"), 9);
  EXPECT_EQ(halton.at("held_back").at("samples"), 1);
  EXPECT_EQ(halton.at("held_back").at("unsolved"), 0);
  EXPECT_LT(halton.at("held_back").at("max_effector_error_m").get<double>(), 5e-4);

  auto refusal = [&](const std::vector<std::string>& overrides) {
    std::vector<std::string> o = overrides;
    o.push_back("control.reduced_model=" + model);
    try {
      hs::run_simulation(deck(o, "refused"), MPI_COMM_SELF);
    } catch (const hs::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(refusal({"mesh.parameters.h=0.007"}).find("made for a mesh of"), std::string::npos);
  EXPECT_NE(refusal({"materials[0].E=2.1e5"}).find("trained on other physics"), std::string::npos);
  EXPECT_NE(refusal({"materials[0].E=2.1e5"}).find(model), std::string::npos);
}

}  // namespace
