// The command line is strict: every argument is hydrosoft's, a PETSc option (or its value), or
// an error naming it. Cases that used to run the deck unchanged and exit 0 are errors now.
#include <gtest/gtest.h>

#include "command_line.hpp"

namespace hs {
namespace {

Arguments parse(std::vector<const char*> words) {
  words.insert(words.begin(), "hydrosoft");
  return parse_arguments(static_cast<int>(words.size()), words.data());
}

std::string error_of(std::vector<const char*> words) {
  try {
    parse(std::move(words));
  } catch (const UsageError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(CommandLine, SplitsOwnArgumentsFromPetscOptions) {
  const Arguments a = parse({"-snes_monitor", "deck.yaml", "--set", "mesh.order=2", "-ksp_type",
                             "cg", "-snes_rtol", "-1e-3", "--targets", "-", "--set", "a.b=[1, 2]"});
  EXPECT_EQ(a.deck, "deck.yaml");
  EXPECT_EQ(a.overrides, (std::vector<std::string>{"mesh.order=2", "a.b=[1, 2]"}));
  EXPECT_EQ(a.targets, "-");
  EXPECT_EQ(a.petsc,
            (std::vector<std::string>{"-snes_monitor", "-ksp_type", "cg", "-snes_rtol", "-1e-3"}));
  EXPECT_EQ(a.petsc_names, (std::vector<std::string>{"-snes_monitor", "-ksp_type", "-snes_rtol"}));
  EXPECT_FALSE(a.help || a.version);
}

TEST(CommandLine, MeshWordWritesTheDecksMesh) {
  const Arguments a = parse({"mesh", "deck.yaml", "out.h5", "--set", "mesh.parameters.h=0.1"});
  EXPECT_TRUE(a.mesh);
  EXPECT_EQ(a.deck, "deck.yaml");
  EXPECT_EQ(a.mesh_output, "out.h5");
  EXPECT_EQ(a.overrides, (std::vector<std::string>{"mesh.parameters.h=0.1"}));
  EXPECT_NE(error_of({"mesh", "deck.yaml"}).find("hydrosoft mesh DECK.yaml OUT.h5"),
            std::string::npos);
  EXPECT_NE(error_of({"mesh", "deck.yaml", "out.h5", "--check"}).find("solves nothing"),
            std::string::npos);
  EXPECT_FALSE(parse({"deck.yaml"}).mesh);
}

TEST(CommandLine, ReduceWordTrainsAModel) {
  const Arguments a = parse({"reduce", "deck.yaml", "-o", "m.h5", "--samples", "9", "--set",
                             "mesh.parameters.h=0.1", "-ksp_type", "cg"});
  EXPECT_TRUE(a.reduce);
  EXPECT_EQ(a.deck, "deck.yaml");
  EXPECT_EQ(a.reduce_output, "m.h5");
  EXPECT_EQ(a.samples, 9);
  EXPECT_EQ(a.petsc, (std::vector<std::string>{"-ksp_type", "cg"}));
  EXPECT_EQ(parse({"reduce", "deck.yaml", "-o", "m.h5"}).samples, 0);  // the default
  EXPECT_NE(error_of({"reduce", "deck.yaml"}).find("hydrosoft reduce DECK.yaml -o MODEL.h5"),
            std::string::npos);
  EXPECT_NE(error_of({"reduce", "deck.yaml", "-o"}).find("-o needs a value"), std::string::npos);
  EXPECT_EQ(error_of({"reduce", "deck.yaml", "-o", "m.h5", "--samples", "2"}),
            "--samples 2: between 3 and 1000");
  EXPECT_EQ(error_of({"reduce", "deck.yaml", "-o", "m.h5", "--samples", "9x"}),
            "--samples 9x: expected a whole number, e.g. --samples 17");
  EXPECT_NE(
      error_of({"reduce", "deck.yaml", "-o", "m.h5", "--targets", "-"}).find("trains a model"),
      std::string::npos);
  EXPECT_EQ(error_of({"deck.yaml", "--samples", "9"}), "--samples: only for hydrosoft reduce");
  const Arguments t = parse(
      {"reduce", "d.yaml", "-o", "m.h5", "--pod-tolerance", "1e-8", "--ecsw-tolerance", "1e-5"});
  EXPECT_EQ(t.pod_tolerance, 1e-8);
  EXPECT_EQ(t.ecsw_tolerance, 1e-5);
  EXPECT_EQ(error_of({"reduce", "d.yaml", "-o", "m.h5", "--ecsw-tolerance", "1"}),
            "--ecsw-tolerance 1: between 0 and 1, both excluded");
  EXPECT_EQ(error_of({"d.yaml", "--pod-tolerance", "1e-8"}),
            "--pod-tolerance: only for hydrosoft reduce");
  EXPECT_FALSE(parse({"deck.yaml"}).reduce);
  EXPECT_EQ(parse({"reduce", "d.yaml", "-o", "m.h5", "--design", "halton"}).design, "halton");
  EXPECT_EQ(error_of({"reduce", "d.yaml", "-o", "m.h5", "--design", "sobol"}),
            "--design sobol: grid or halton");
  EXPECT_EQ(error_of({"d.yaml", "--design", "grid"}), "--design: only for hydrosoft reduce");
}

TEST(CommandLine, QuietAndVerboseAreOursNotPetscs) {
  const Arguments q = parse({"deck.yaml", "-q", "-snes_monitor"});
  EXPECT_TRUE(q.quiet);
  EXPECT_FALSE(q.verbose);
  EXPECT_EQ(q.petsc, (std::vector<std::string>{"-snes_monitor"}));
  const Arguments v = parse({"--verbose", "deck.yaml"});
  EXPECT_TRUE(v.verbose);
  EXPECT_TRUE(v.petsc.empty());
  EXPECT_NE(error_of({"deck.yaml", "--quie"}).find("did you mean --quiet?"), std::string::npos);
}

TEST(CommandLine, HelpAndVersion) {
  EXPECT_TRUE(parse({"-h"}).help);
  EXPECT_TRUE(parse({"--help"}).help);
  EXPECT_TRUE(parse({"--version"}).version);
}

TEST(CommandLine, MistypedArgumentsAreErrorsThatNameThem) {
  EXPECT_EQ(error_of({"deck.yaml", "--sett", "mesh.order=2"}),
            "unknown argument '--sett' (did you mean --set?); PETSc options take one dash, e.g. "
            "-snes_monitor");
  EXPECT_EQ(error_of({"deck.yaml", "--debug"}),
            "unknown argument '--debug'; PETSc options take one dash, e.g. -snes_monitor");
  EXPECT_EQ(error_of({"deck.yaml", "mesh.order=2"}),
            "unexpected argument 'mesh.order=2' after the deck deck.yaml (to override a key: --set "
            "mesh.order=2)");
  EXPECT_EQ(error_of({"deck.yaml", "--set"}), "--set: needs a value (--set key=value)");
  EXPECT_EQ(error_of({"deck.yaml", "--set", "--targets", "-"}),
            "--set: needs a value (--set key=value)");
  EXPECT_EQ(error_of({"deck.yaml", "--set", "mesh.order"}),
            "--set mesh.order: expected key=value, e.g. --set mesh.order=2");
  EXPECT_EQ(error_of({"deck.yaml", "--targets"}), "--targets: needs a value (--targets -)");
  EXPECT_EQ(error_of({"deck.yaml", "--restart"}),
            "--restart: needs a value (--restart FOLDER, a run's output folder)");
  EXPECT_EQ(error_of({"--check", "deck.yaml", "--restart", "out/x"}),
            "--check: --restart does not apply (it solves nothing)");
  EXPECT_EQ(parse({"deck.yaml", "--restart", "out/x.failed"}).restart, "out/x.failed");
  EXPECT_EQ(error_of({"a.yaml", "b.yaml"}), "unexpected argument 'b.yaml' after the deck a.yaml");
}

}  // namespace
}  // namespace hs
