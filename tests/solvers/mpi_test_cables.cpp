// Cables against exact geometry, on 1 and 2 ranks: the length of the path of material points
// under an affine deformation (which P1 elements carry exactly), its derivative
// g = -dL/du against central differences, the net force of a unit tension (the pull
// point's direction, or zero for a cable between body points only); and the inverse
// controller, which must find the tension of a forward run from the target it reached and
// stop at a force bound it cannot pass.
#include <gtest/gtest.h>
#include <petscvec.h>

#include <cmath>

#include "common/error.hpp"
#include "control_scene.hpp"
#include "deck/deck.hpp"
#include "mesh/distribution.hpp"
#include "mesh/gmsh_io.hpp"
#include "solvers/constraints/cable.hpp"
#include "solvers/constraints/cable_path.hpp"
#include "solvers/constraints/capstan_cable.hpp"
#include "solvers/inverse_controller.hpp"
#include "solvers/petsc_check.hpp"
#include "solvers/problem.hpp"

namespace {

const std::string kSource = HYDROSOFT_SOURCE_DIR;

struct Body : hs_test::DeckProblem {
  Body()
      : DeckProblem("finger_pneumatic.yaml",
                    hs_test::compressible_finger({"mesh.parameters.h=0.006"})) {}
  // u = A X at every node (owned entries; the new numbering of the distribution).
  hs::VecHandle affine(const double A[3][3]) {
    hs::VecHandle u(problem->create_vector());
    for (int64_t l = 0; l < dist.num_owned(); ++l) {
      const int64_t id = dist.local_nodes[l];
      for (int d = 0; d < 3; ++d) {
        double v = 0;
        for (int e = 0; e < 3; ++e) v += A[d][e] * dist.x[3 * l + e];
        HS_PETSC(VecSetValue(u, 3 * id + d, v, INSERT_VALUES));
      }
    }
    HS_PETSC(VecAssemblyBegin(u));
    HS_PETSC(VecAssemblyEnd(u));
    return u;
  }
};

hs::CableConfig bottom_cable(bool pull_point) {
  hs::CableConfig c;
  c.name = "tendon";
  c.points = {{0.085, 0.002, -0.006}, {0.05, 0.0, -0.0065}, {0.012, -0.001, -0.006}};
  if (pull_point) c.pull_point = std::array<double, 3>{-0.02, 0.0, -0.006};
  return c;
}

double distance(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

TEST(Cables, LengthUnderAnAffineDeformationIsExact) {
  Body b;
  const double A[3][3] = {{0.02, -0.05, 0.01}, {0.03, -0.01, 0.04}, {-0.02, 0.06, 0.015}};
  const hs::VecHandle u(b.affine(A));
  for (bool pull : {false, true}) {
    const hs::CableConfig config = bottom_cable(pull);
    hs::CablePath cable(config, *b.problem, "test");
    auto map = [&](const std::array<double, 3>& X) {
      std::array<double, 3> x;
      for (int d = 0; d < 3; ++d) x[d] = X[d] + A[d][0] * X[0] + A[d][1] * X[1] + A[d][2] * X[2];
      return x;
    };
    double L0 = 0, L = 0;
    for (size_t i = 0; i + 1 < config.points.size(); ++i) {
      L0 += distance(config.points[i], config.points[i + 1]);
      L += distance(map(config.points[i]), map(config.points[i + 1]));
    }
    if (pull) {  // the pull point is fixed in space
      L0 += distance(*config.pull_point, config.points.back());
      L += distance(*config.pull_point, map(config.points.back()));
    }
    const hs::VecHandle zero(b.problem->create_vector());
    EXPECT_NEAR(cable.length(zero), L0, 1e-15) << pull;
    EXPECT_NEAR(cable.length(u), L, 1e-14) << pull;
  }
}

TEST(Cables, PullDirectionIsMinusTheLengthGradient) {
  Body b;
  const double A[3][3] = {{0.05, 0.02, -0.03}, {-0.04, 0.01, 0.02}, {0.03, -0.02, 0.04}};
  const double B[3][3] = {{0.3, -0.1, 0.2}, {0.1, 0.4, -0.2}, {-0.3, 0.2, 0.1}};
  const hs::VecHandle u(b.affine(A)), du(b.affine(B)), g(b.problem->create_vector());
  const hs::VecHandle up(b.problem->create_vector()), um(b.problem->create_vector());
  for (bool pull : {false, true}) {
    hs::CablePath cable(bottom_cable(pull), *b.problem, "test");
    cable.pull_direction(u, g);
    const double h = 1e-6;
    VecWAXPY(up, h, du, u);
    VecWAXPY(um, -h, du, u);
    const double dL = (cable.length(up) - cable.length(um)) / (2 * h);
    PetscScalar gdu = 0;
    VecDot(g, du, &gdu);
    EXPECT_NEAR(-gdu, dL, 1e-8 * std::abs(dL)) << pull;
    // Net force of a unit tension: the sum of g over the x, y, z dofs. Between body points
    // only, the cable is internal (zero); with a pull point, the unit vector towards it.
    std::array<double, 3> net{0, 0, 0};
    const PetscScalar* a;
    PetscInt lo, hi;
    VecGetOwnershipRange(g, &lo, &hi);
    VecGetArrayRead(g, &a);
    for (PetscInt i = lo; i < hi; ++i) net[i % 3] += a[i - lo];
    VecRestoreArrayRead(g, &a);
    MPI_Allreduce(MPI_IN_PLACE, net.data(), 3, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
    std::array<double, 3> expected{0, 0, 0};
    if (pull) {
      const auto x = cable.positions(u);
      const std::array<double, 3> last{x[6], x[7], x[8]};
      const hs::CableConfig pulled = bottom_cable(true);
      const auto& p = *pulled.pull_point;
      for (int d = 0; d < 3; ++d) expected[d] = (p[d] - last[d]) / distance(p, last);
    }
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(net[d], expected[d], 1e-13) << pull << " " << d;
  }
}

TEST(Cables, OutsidePointIsRefused) {
  Body b;
  hs::CableConfig c = bottom_cable(true);
  c.points[1] = {0.05, 0.0, 0.02};  // above the finger (T = 16 mm)
  try {
    hs::CablePath cable(c, *b.problem, "deck.yaml");
    FAIL() << "a point outside the mesh was accepted";
  } catch (const hs::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cables 'tendon' points[1]"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("outside the mesh"), std::string::npos) << e.what();
  }
}

// The finger of input/finger_cable.yaml (its tendon, no cavity), effector at the tip.
struct CableScene : hs_test::ControlScene {
  explicit CableScene(double max_force, double friction = 0)
      : ControlScene(
            "finger_cable.yaml", {0.09, 0.0, 0.0}, actuator(max_force),
            {"mesh.parameters.h=0.006", "cables[0].friction=" + std::to_string(friction)}) {}
  static hs::ActuatorConfig actuator(double max_force) {
    hs::ActuatorConfig a;
    a.constraint = "tendon";
    a.min_multiplier = 0;
    a.max_multiplier = max_force;
    return a;
  }
};

TEST(Cables, ControllerFindsTheTensionOfAForwardRun) {
  CableScene s(10.0);
  const double tension = 0.6;  // N
  const auto target = s.forward(tension);
  ASSERT_LT(target[2], -0.0135);  // the tendon curls the finger down, below its rest (-12.7 mm)
  const hs::ControlStepReport r = s.drive(target, 8);
  EXPECT_LT(r.error, 1e-4);
  EXPECT_NEAR(r.actuation[0], tension, 1e-3 * tension);
  EXPECT_FALSE(r.saturated[0]);
  EXPECT_LT(r.kkt_residual, 1e-8);
}

TEST(Cables, ACableCannotPush) {
  // A target above the rest position would need a push: the tension stays at 0, saturated,
  // and the tip stays where it hangs.
  CableScene s(10.0);
  const auto rest = s.forward(0.0);
  const hs::ControlStepReport r = s.drive({0.09, 0.0, rest[2] + 0.005}, 4);
  EXPECT_NEAR(r.actuation[0], 0.0, 1e-12);  // at its bound, to round-off (N)
  EXPECT_TRUE(r.saturated[0]);
  EXPECT_NEAR(r.reached[2], rest[2], 1e-9);
}

// J du against central differences of the residual, with a tension on the cable: the
// cable's turning stiffness T (I - e e^T) / l is in J (without it the two differ by about
// T / l per unit displacement of its points); with capstan friction, the unsymmetric
// stiffness of the friction-weighted forces.
void expect_tangent_matches_differences(double friction) {
  CableScene s(10.0, friction);
  hs::Constraint& cable = (*s.cavities)[0];
  cable.set_multiplier(0.8);
  const hs::VecHandle u(s.problem->create_vector()), du(s.problem->create_vector());
  VecCopy(s.rest, u);
  const double B[3][3] = {{0.3, -0.1, 0.2}, {0.1, 0.4, -0.2}, {-0.3, 0.2, 0.1}};
  PetscInt lo, hi;
  VecGetOwnershipRange(du, &lo, &hi);
  for (PetscInt i = lo; i < hi; ++i)
    VecSetValue(du, i, 1e-3 * B[i % 3][(i / 3) % 3], INSERT_VALUES);
  VecAssemblyBegin(du);
  VecAssemblyEnd(du);
  s.problem->zero_constrained(du);
  const hs::MatHandle J(s.problem->create_matrix());
  hs::ConstraintLinearization lin;
  std::vector<double> c;
  const hs::VecHandle R(s.problem->create_vector()), Rp(s.problem->create_vector()),
      Rm(s.problem->create_vector()), up(s.problem->create_vector()),
      Jdu(s.problem->create_vector());
  ASSERT_TRUE(s.cavities->residual(u, 1.0, R, c));
  ASSERT_TRUE(s.cavities->linearize(u, 1.0, J, lin));
  MatMult(J, du, Jdu);
  const double h = 1e-4;
  VecWAXPY(up, h, du, u);
  s.cavities->residual(up, 1.0, Rp, c);
  VecWAXPY(up, -h, du, u);
  s.cavities->residual(up, 1.0, Rm, c);
  VecAXPY(Rp, -1.0, Rm);
  VecScale(Rp, 1.0 / (2 * h));
  PetscReal ref = 0, diff = 0;
  VecNorm(Rp, NORM_2, &ref);
  VecAXPY(Rp, -1.0, Jdu);
  VecNorm(Rp, NORM_2, &diff);
  EXPECT_LT(diff, 1e-6 * ref) << diff << " of " << ref << ", friction " << friction;
}

TEST(Cables, TangentWithTheCableStiffnessMatchesDifferences) {
  expect_tangent_matches_differences(0.0);
}

TEST(CapstanCables, TangentWithTheFrictionStiffnessMatchesDifferences) {
  expect_tangent_matches_differences(0.3);
}

TEST(CapstanCables, WithoutFrictionTheyPullAsTheFrictionlessCable) {
  // Two implementations of the same forces: the capstan law at mu = 0 and the cable's -dL/du.
  Body b;
  hs::CableConfig config = bottom_cable(true);
  hs::Config deck;
  deck.deck_path = "test";
  hs::ConstraintContext context(*b.problem, deck);
  hs::Cable plain(config, context);
  hs::CapstanCable capstan(config, context);
  const double A[3][3] = {{0.02, 0.01, -0.03}, {0.0, -0.01, 0.02}, {0.05, 0.01, 0.01}};
  const hs::VecHandle u(b.affine(A)), g0(b.problem->create_vector()),
      g1(b.problem->create_vector());
  plain.forces(u, g0);
  capstan.forces(u, g1);
  PetscReal ref = 0, diff = 0;
  VecNorm(g0, NORM_2, &ref);
  VecAXPY(g1, -1.0, g0);
  VecNorm(g1, NORM_2, &diff);
  EXPECT_GT(ref, 0.5);
  EXPECT_LT(diff, 1e-14 * ref);
}

TEST(CapstanCables, FrictionHoldsBackTheCurlAndTheControllerFindsTheTension) {
  // The same motor tension curls the finger less when the eyelets hold part of it back; the
  // controller, given the tip a forward run reached, finds that run's motor tension.
  const double tension = 0.6;  // N
  CableScene plain(10.0), rough(10.0, 0.3);
  const auto rest = plain.forward(0.0);
  const auto free_tip = plain.forward(tension);
  const auto target = rough.forward(tension);
  ASSERT_LT(free_tip[2], rest[2] - 1e-3);
  EXPECT_LT(target[2], rest[2] - 1e-4);      // it still curls
  EXPECT_GT(target[2], free_tip[2] + 1e-4);  // but less
  const hs::ControlStepReport r = rough.drive(target, 8);
  EXPECT_LT(r.error, 1e-4);
  EXPECT_NEAR(r.actuation[0], tension, 1e-3 * tension);
}

}  // namespace
