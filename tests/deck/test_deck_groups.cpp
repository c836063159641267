// check_groups: the groups a deck names against a small hand-built mesh.
#include <gtest/gtest.h>

#include "common/error.hpp"
#include "deck/deck.hpp"

namespace hs {
namespace {

// Two P1 tetrahedra sharing the face (1, 2, 3): volume "body" and volume "insert"; the
// shared face is the surface "inner"; node 4 alone is the point group "tip"; "empty" is a
// group without nodes.
Mesh two_tet_mesh() {
  Mesh m;
  m.order = 1;
  m.x = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  m.tets = {0, 1, 2, 3, 1, 2, 3, 4};
  m.tet_volume = {0, 1};
  m.volume_names = {"body", "insert"};
  m.surfaces["inner"] = {1, 3, 2};
  m.surface_tets["inner"] = {0};
  m.node_groups = {{"body", {0, 1, 2, 3}},
                   {"insert", {1, 2, 3, 4}},
                   {"inner", {1, 2, 3}},
                   {"tip", {4}},
                   {"empty", {}}};
  return m;
}

Config valid_config() {
  Config c;
  c.deck_path = "robot.yaml";
  c.mesh.file = "robot.msh";
  c.materials = {MaterialConfig{}, MaterialConfig{}};
  c.materials[0].group = "body";
  c.materials[1].group = "insert";
  c.dirichlet = {DirichletConfig{}};
  c.dirichlet[0].group = "tip";
  c.pressures = {PressureConfig{"inner", 1.0}};
  return c;
}

std::string error_of(const Config& c) {
  try {
    check_groups(c, groups_of(two_tet_mesh()));
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

const std::string kListing =
    "(mesh robot.msh has volumes: body, insert; surfaces: inner; other groups: empty, tip)";

TEST(CheckGroups, AcceptsAValidDeck) {
  EXPECT_NO_THROW(check_groups(valid_config(), groups_of(two_tet_mesh())));
}

TEST(CheckGroups, MaterialGroupMissing) {
  Config c = valid_config();
  c.materials[1].group = "insrt";
  // Both the misspelt group and the volume left without material are errors; the first wins.
  EXPECT_EQ(error_of(c),
            "robot.yaml: materials[1].group: group 'insrt' is not in the mesh " + kListing);
}

TEST(CheckGroups, MaterialGroupNotAVolume) {
  Config c = valid_config();
  c.materials[1].group = "inner";
  EXPECT_EQ(error_of(c),
            "robot.yaml: materials[1].group: group 'inner' is not a volume " + kListing);
}

TEST(CheckGroups, VolumeWithoutMaterial) {
  Config c = valid_config();
  c.materials.pop_back();
  EXPECT_EQ(error_of(c),
            "robot.yaml: materials: volume 'insert' of the mesh has no material " + kListing);
}

TEST(CheckGroups, BoundaryGroupMissingOrEmpty) {
  Config c = valid_config();
  c.dirichlet.push_back(DirichletConfig{});
  c.dirichlet[1].group = "clamp";
  EXPECT_EQ(error_of(c),
            "robot.yaml: boundary[1].group: group 'clamp' is not in the mesh " + kListing);
  c.dirichlet[1].group = "empty";
  EXPECT_EQ(error_of(c), "robot.yaml: boundary[1].group: group 'empty' has no nodes " + kListing);
  c.dirichlet[1].group = "body";  // any group with nodes may be constrained
  EXPECT_EQ(error_of(c), "no error");
}

TEST(CheckGroups, TractionGroupNotASurface) {
  Config c = valid_config();
  c.tractions.push_back({"tip", {0, 1, 0}});
  EXPECT_EQ(error_of(c),
            "robot.yaml: loads.traction[0].group: group 'tip' is not a surface " + kListing);
}

TEST(CheckGroups, PressureGroupNotASurface) {
  Config c = valid_config();
  c.pressures[0].group = "tip";
  EXPECT_EQ(error_of(c),
            "robot.yaml: loads.pressure[0].group: group 'tip' is not a surface " + kListing);
  c.pressures[0].group = "outer";
  EXPECT_EQ(error_of(c),
            "robot.yaml: loads.pressure[0].group: group 'outer' is not in the mesh " + kListing);
}

TEST(CheckGroups, ContactSurfacesAreSurfaces) {
  Config c = valid_config();
  c.contact.surfaces = {"inner", "tip"};
  EXPECT_EQ(error_of(c),
            "robot.yaml: contact.surfaces[1]: group 'tip' is not a surface " + kListing);
  c.contact.surfaces = {"inner"};
  EXPECT_EQ(error_of(c), "no error");
}

TEST(CheckGroups, CavityAndTipGroupsAreSurfaces) {
  Config c = valid_config();
  c.cavities = {CavityConfig{}};
  c.cavities[0].group = "inner";
  c.tip = TipConfig{"inner"};
  EXPECT_EQ(error_of(c), "no error");
  c.cavities[0].group = "tip";
  EXPECT_EQ(error_of(c), "robot.yaml: cavities[0].group: group 'tip' is not a surface " + kListing);
  c.cavities[0].group = "cavity";
  EXPECT_EQ(error_of(c),
            "robot.yaml: cavities[0].group: group 'cavity' is not in the mesh " + kListing);
  c.cavities[0].group = "inner";
  c.tip = TipConfig{"body"};
  EXPECT_EQ(error_of(c), "robot.yaml: tip.group: group 'body' is not a surface " + kListing);
  c.tip = TipConfig{"empty"};
  EXPECT_EQ(error_of(c), "robot.yaml: tip.group: group 'empty' has no nodes " + kListing);
}

// An effector's point group must have exactly one node; a material point names no group.
TEST(CheckGroups, EffectorPointsHaveOneNode) {
  Config c = valid_config();
  c.control = ControlConfig{};
  c.control->effectors = {EffectorConfig{}, EffectorConfig{}};
  c.control->effectors[0].name = "side";
  c.control->effectors[0].position = {0.5, 0.1, 0.1};  // no point: not a group
  c.control->effectors[1].name = "tip";
  c.control->effectors[1].point = "tip";
  EXPECT_EQ(error_of(c), "no error");
  c.control->effectors[1].point = "inner";
  EXPECT_EQ(error_of(c),
            "robot.yaml: control.effectors[1].point: group 'inner' has 3 nodes, an effector "
            "point needs exactly one " +
                kListing);
  c.control->effectors[1].point = "effector";
  EXPECT_EQ(error_of(c),
            "robot.yaml: control.effectors[1].point: group 'effector' is not in the "
            "mesh " +
                kListing);
  c.control->effectors[1].point = "empty";
  EXPECT_EQ(error_of(c),
            "robot.yaml: control.effectors[1].point: group 'empty' has no nodes " + kListing);
}

}  // namespace
}  // namespace hs
