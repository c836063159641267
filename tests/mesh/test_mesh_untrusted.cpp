// Untrusted meshes (docs/reliability.md, "Untrusted meshes and surfaces"): a .geo that runs
// commands or reaches outside its folders is refused before gmsh runs it; meshing leaves no
// file behind; mesh.max_elements stops huge meshes; a .msh whose counts its size cannot back
// is refused before gmsh allocates for them; bad coordinates and bad elements are refused
// naming the node or element; a mesh far from metres draws a warning. Every file is written
// by the test into a temporary folder that the test removes.
#include <gmsh.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "mesh/geo_guard.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/msh_prescan.hpp"
#include "mesh_test_util.hpp"

namespace hs::test {
namespace {
namespace test_mesh_untrusted {

namespace fs = std::filesystem;

Mesh load(const std::string& file, int64_t max_elements = 20'000'000, int refine = 0,
          std::map<std::string, double> parameters = {}, bool trust_geo = false) {
  MeshConfig cfg;
  cfg.file = file;
  cfg.max_elements = max_elements;
  cfg.refine = refine;
  cfg.parameters = std::move(parameters);
  cfg.trust_geo = trust_geo;
  return load_mesh(cfg);
}

// A unit cube that gmsh meshes in a moment, with `before` in front of it.
std::string cube_geo(const TempDir& dir, const std::string& name, const std::string& before) {
  const std::string path = dir.file(name);
  std::ofstream(path) << before
                      << "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\n"
                         "Physical Volume(\"body\") = {1};\n";
  return path;
}

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// The text with the first `from` after `anchor` replaced by `to`.
std::string replace_after(std::string text, const std::string& anchor, const std::string& from,
                          const std::string& to) {
  const size_t at = text.find(from, text.find(anchor));
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// ---- 1. A .geo is code: commands and files outside its folders are refused -------------

TEST(UntrustedGeo, ShellCommandIsRefusedBeforeItRuns) {
  TempDir dir;
  const std::string marker = dir.file("ran");
  const std::string geo =
      cube_geo(dir, "evil.geo", "// a cube\nSystemCall \"touch " + marker + "\";\n");
  expect_input_error([&] { load(geo); },
                     {geo, "SystemCall", "shell command", "mesh.trust_geo", "(line 2)"});
  EXPECT_FALSE(fs::exists(marker));
}

TEST(UntrustedGeo, EveryCommandThatReachesOutIsNamedWithItsLine) {
  TempDir dir;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"System \"ls\";", "System"},
      {"NonBlockingSystemCall \"ls\";", "NonBlockingSystemCall"},
      {"OnelabRun(\"x\", \"ls\");", "OnelabRun"},
      {"Exit;", "Exit"},
      {"n = GetValue(\"size?\", 1);", "GetValue"},
      {"Save \"copy.msh\";", "Save"},
      {"Print \"picture.png\";", "Print"},
      {"Printf(\"%g\", 1) > \"out.txt\";", "Printf"},
      {"CreateDir \"sub\";", "CreateDir"},
      {"DeleteFile \"other.geo\";", "DeleteFile"},
      {"Include \"/etc/passwd\";", "Include \"/etc/passwd\""},
      {"Merge \"../outside.step\";", "Merge \"../outside.step\""},
      {"Include StrCat(\"a\", \".geo\");", "Include"},
      {"ShapeFromFile(\"/tmp/x.step\");", "ShapeFromFile"},
      {"General.SessionFileName = \"x\";", "General.SessionFileName"},
      {"Solver.Executable0 = \"sh\";", "Solver.Executable0"},
      {"s = \"/etc/shadow\";", "\"/etc/shadow\""},
      {"s = \"~/.bashrc\";", "\"~/.bashrc\""},
  };
  for (const auto& [command, named] : cases) {
    const std::string geo = cube_geo(dir, "case.geo", "a = 1;\n/* line 2 */\n" + command + "\n");
    SCOPED_TRACE(command);
    expect_input_error([&] { check_untrusted_geo(geo, {}); }, {geo + ": " + named, "(line 3)"});
  }
}

TEST(UntrustedGeo, CommentsPlainPrintfAndFilesInsideItsFoldersAreFine) {
  TempDir dir;
  fs::create_directory(dir.file("parts"));
  write(dir.file("parts/size.geo"), "DefineConstant[ h = 0.5 ];\n");
  const std::string geo = cube_geo(dir, "good.geo",
                                   "// SystemCall \"rm -rf /\"; in a comment\n"
                                   "/* Include \"/etc/passwd\"; */\n"
                                   "Include \"parts/size.geo\";\n"
                                   "Printf(\"SystemCall %g / 2\", h);\n"
                                   "Mesh.MeshSizeMax = h;\n");
  EXPECT_NO_THROW(check_untrusted_geo(geo, {}));
  EXPECT_GT(load(geo).num_tets(), 0);
}

TEST(UntrustedGeo, AnIncludedFileIsCheckedToo) {
  TempDir dir;
  write(dir.file("inner.geo"), "x = 1;\nSystemCall \"ls\";\n");
  const std::string geo = cube_geo(dir, "outer.geo", "Include \"inner.geo\";\n");
  expect_input_error([&] { load(geo); }, {dir.file("inner.geo") + ": SystemCall", "(line 2)"});
}

TEST(UntrustedGeo, TheDecksFolderIsAllowedToo) {
  TempDir dir;
  fs::create_directory(dir.file("deck"));
  fs::create_directory(dir.file("meshes"));
  write(dir.file("deck/size.geo"), "h = 0.5;\n");
  const std::string geo = cube_geo(dir, "meshes/body.geo", "Include \"../deck/size.geo\";\n");
  expect_input_error([&] { check_untrusted_geo(geo, {}); }, {"outside"});
  EXPECT_NO_THROW(check_untrusted_geo(geo, {dir.file("deck")}));
}

TEST(UntrustedGeo, TrustedFileRunsAsItIs) {
  TempDir dir;
  const std::string geo =
      cube_geo(dir, "trusted.geo", "Printf(\"written\") > \"" + dir.file("out.txt") + "\";\n");
  expect_input_error([&] { load(geo); }, {"Printf", "writes to a file"});
  EXPECT_FALSE(fs::exists(dir.file("out.txt")));
  EXPECT_GT(load(geo, 20'000'000, 0, {}, /*trust_geo=*/true).num_tets(), 0);
  EXPECT_TRUE(fs::exists(dir.file("out.txt")));
}

TEST(UntrustedGeo, EveryShippedGeoPasses) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(std::string(HYDROSOFT_SOURCE_DIR) + "/meshes"))
    if (entry.path().extension() == ".geo") {
      SCOPED_TRACE(entry.path().string());
      EXPECT_NO_THROW(check_untrusted_geo(entry.path().string(), {}));
      ++count;
    }
  EXPECT_GE(count, 7);
}

// ---- 1b. What gmsh reads that the .geo only names -----------------------------------------

// gmsh reads a merged file of an extension it does not know as a script: the payload ran.
TEST(UntrustedGeo, AMergedFileOfAnyNameIsCheckedAsGmshReadsIt) {
  TempDir dir;
  const std::string marker = dir.file("ran");
  write(dir.file("payload.txt"), "SystemCall \"touch " + marker + "\";\n");
  const std::string geo =
      cube_geo(dir, "merge.geo", "Merge \"payload.txt\";\nDefineConstant[ h = 1 ];\n");
  expect_input_error([&] { load(geo); },
                     {dir.file("payload.txt") + ": SystemCall", "shell command", "(line 1)"});
  expect_input_error(
      [&] {
        load(geo, 20'000'000, 0, {{"h", 0.5}});
      },
      {dir.file("payload.txt") + ": SystemCall"});
  EXPECT_FALSE(fs::exists(marker));
  // A script named as a mesh is read as a script: gmsh looks at the first line, not the name.
  write(dir.file("payload.msh"), "SystemCall \"touch " + marker + "\";\n");
  const std::string named = cube_geo(dir, "named.geo", "Merge \"payload.msh\";\n");
  expect_input_error([&] { load(named); }, {dir.file("payload.msh") + ": SystemCall"});
  EXPECT_FALSE(fs::exists(marker));
}

TEST(UntrustedGeo, FilesGmshWouldNotReadAsScriptMeshOrCadAreRefused) {
  TempDir dir;
  for (const std::string name : {"data.msh.gz", "model.pro", "run.py", "view.pos", "cube.stl"}) {
    SCOPED_TRACE(name);
    write(dir.file(name), name == "view.pos" ? "$PostFormat\n" : "solid x\n");
    const std::string geo = cube_geo(dir, "case.geo", "a = 1;\nMerge \"" + name + "\";\n");
    expect_input_error([&] { load(geo); }, {geo + ": Merge \"" + name + "\"", "(line 2)"});
  }
  write(dir.file("part.txt"), "ISO-10303-21;\n");
  const std::string shape = cube_geo(dir, "shape.geo", "ShapeFromFile(\"part.txt\");\n");
  expect_input_error([&] { load(shape); }, {"ShapeFromFile \"part.txt\"", "CAD files only"});
}

// gmsh merges "<file>.opt" after every file it merges, unasked: a SystemCall there ran, beside a
// .geo (`hydrosoft DECK` and `hydrosoft mesh`) as beside a .msh.
TEST(UntrustedGeo, TheOptionsFileBesideEveryMergedFileIsChecked) {
  TempDir dir;
  const std::string marker = dir.file("ran");
  const std::string payload = "Mesh.MeshSizeMax = 0.5;\nSystemCall \"touch " + marker + "\";\n";
  const std::string geo = cube_geo(dir, "body.geo", "");
  write(geo + ".opt", payload);
  expect_input_error([&] { load(geo); }, {geo + ".opt: SystemCall", "(line 2)"});
  write(dir.file("body.geo.opt"), "Mesh.MeshSizeMax = 0.5;\n");
  write(dir.file("body.geo.opt.opt"), payload);  // and beside that one, in turn
  expect_input_error([&] { load(geo); }, {geo + ".opt.opt: SystemCall"});
  const std::string msh = corner_tet().write(dir, "corner.msh");
  EXPECT_EQ(load(msh).num_tets(), 1);
  write(msh + ".opt", payload);
  expect_input_error([&] { load(msh); }, {msh + ".opt: SystemCall"});
  write(dir.file("inner.geo"), "x = 1;\n");
  write(dir.file("inner.geo.opt"), payload);
  const std::string outer = cube_geo(dir, "outer.geo", "Merge \"inner.geo\";\n");
  expect_input_error([&] { load(outer); }, {dir.file("inner.geo.opt") + ": SystemCall"});
  EXPECT_FALSE(fs::exists(marker));
}

// A crafted .msh merged by a .geo skipped the .msh checks: gmsh crashed on it (SIGSEGV).
TEST(UntrustedGeo, AMergedMeshGetsTheMeshChecks) {
  TempDir dir;
  const std::string good = read(corner_tet().write(dir, "corner.msh"));
  write(dir.file("bad.msh"), replace_after(good, "$Nodes", "1 4 1 4", "1 16777216 1 16777216"));
  const std::string geo = cube_geo(dir, "merge.geo", "Merge \"bad.msh\";\n");
  expect_input_error([&] { load(geo); }, {dir.file("bad.msh") + ": $Nodes: claims 16777216"});
}

// A file named .msh that does not begin as a mesh is run by gmsh as a script.
TEST(UntrustedMsh, AMshThatIsAScriptIsRefused) {
  TempDir dir;
  const std::string marker = dir.file("ran");
  const std::string good = read(corner_tet().write(dir, "corner.msh"));
  const std::string msh = dir.file("script.msh");
  write(msh, "SystemCall \"touch " + marker + "\";\n" + good);
  expect_input_error([&] { load(msh); }, {msh + ": its first line is not $MeshFormat",
                                          "gmsh would run the file as a .geo script"});
  EXPECT_FALSE(fs::exists(marker));
}

// ---- 2. Nothing left behind; a limit on the element count ------------------------------

// The files of `dir`, by name.
std::vector<std::string> files_in(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  return names;
}

TEST(MeshingLeavesNothing, NotEvenWhenGmshEndsItsProcess) {
  TempDir dir, tmp;
  // A trusted .geo with deck parameters whose Exit ends gmsh's process inside gmsh: no
  // destructor runs there. The run goes on to say so, and the temporary folder stays empty.
  const std::string geo = cube_geo(dir, "exit.geo", "DefineConstant[ h = 0.5 ];\nExit;\n");
  const char* old = getenv("TMPDIR");
  const std::string saved = old ? old : "";
  setenv("TMPDIR", tmp.file("").c_str(), 1);
  expect_input_error(
      [&] {
        load(geo, 20'000'000, 0, {{"h", 0.3}}, /*trust_geo=*/true);
      },
      {geo + ": gmsh was told to exit before reading it to the end"});
  if (old)
    setenv("TMPDIR", saved.c_str(), 1);
  else
    unsetenv("TMPDIR");
  EXPECT_EQ(files_in(tmp.file("")), std::vector<std::string>{});
}

TEST(MeshingLeavesNothing, WhenAParameterIsRefused) {
  TempDir dir, tmp;
  const std::string geo = cube_geo(dir, "plain.geo", "h = 0.5;\n");
  const char* old = getenv("TMPDIR");
  const std::string saved = old ? old : "";
  setenv("TMPDIR", tmp.file("").c_str(), 1);
  expect_input_error([&] { load(geo, 20'000'000, 0, {{"h", 0.3}}); }, {"DefineConstant"});
  if (old)
    setenv("TMPDIR", saved.c_str(), 1);
  else
    unsetenv("TMPDIR");
  EXPECT_EQ(files_in(tmp.file("")), std::vector<std::string>{});
}

TEST(MaxElements, HugeParametersAreRefusedBeforeMeshing) {
  const auto start = std::chrono::steady_clock::now();
  expect_input_error(
      [] {
        load(source_mesh("cantilever.geo"), 20'000'000, 0, {{"L", 1e9}});
      },
      {"cantilever.geo: mesh.max_elements", "at least", "above the limit of 20000000"});
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 30);  // refused before meshing, not after
}

// Above the limit's reach (the limit raised out of the way), gmsh fails inside its parallel
// 2D mesher, whence no exception can return to the caller: gmsh's process still answers with
// gmsh's message, an input error like any other (before gmsh had a process of its own, the
// run ended there, with the message, through std::terminate).
TEST(MaxElements, GmshErrorInsideItsParallelMesherIsReported) {
  expect_input_error(
      [] {
        load(source_mesh("cantilever.geo"), INT64_MAX, 0, {{"L", 1e9}});
      },
      {source_mesh("cantilever.geo") + ": gmsh: "});
}

TEST(MaxElements, CountedAfterMeshingAndBeforeRefinement) {
  const Mesh m = load(source_mesh("block.geo"));
  const int64_t n = m.num_tets();
  EXPECT_EQ(load(source_mesh("block.geo"), n).num_tets(), n);
  expect_input_error([&] { load(source_mesh("block.geo"), n - 1); },
                     {"mesh.max_elements", "the mesh has " + std::to_string(n) + " tetrahedra"});
  expect_input_error([&] { load(source_mesh("block.geo"), 8 * n - 1, 1); },
                     {"mesh.max_elements", std::to_string(8 * n) + " after 1 refinements"});
}

TEST(MaxElements, MshIsCountedFromItsHeader) {
  TempDir dir;
  MshFile f;  // two tetrahedra sharing the face z = 0
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}};
  f.blocks = {{3, 4, {{1, 2, 3, 4}, {1, 3, 2, 5}}}};
  const std::string path = f.write(dir, "two.msh");
  EXPECT_EQ(prescan_msh(path).tets, 2);
  EXPECT_EQ(load(path, 2).num_tets(), 2);
  expect_input_error([&] { load(path, 1); },
                     {path + ": mesh.max_elements", "$Elements section holds 2 tetrahedra"});
}

// ---- 3. Counts against the file's size; coordinates ------------------------------------

TEST(MshCounts, NodesClaimedBeyondTheFilesSizeAreRefused) {
  TempDir dir;
  const std::string good = read(corner_tet().write(dir, "corner.msh"));
  // 2^24 nodes would take gmsh a quarter of a gigabyte before it read the first one.
  const std::string path = dir.file("claim.msh");
  write(path, replace_after(good, "$Nodes", "1 4 1 4", "1 16777216 1 16777216"));
  expect_input_error([&] { load(path); },
                     {path + ": $Nodes: claims 16777216 nodes", "-byte file", "(line "});
  write(path, replace_after(good, "$Nodes", "3 1 0 4", "3 1 0 16777216"));
  expect_input_error([&] { load(path); }, {"$Nodes", "16777216 nodes in entity block 1"});
  write(path, replace_after(good, "$Nodes", "3 1 0 4", "3 1 0 -4"));
  expect_input_error([&] { load(path); }, {"$Nodes", "-4", "cannot be negative"});
  write(path, replace_after(good, "$Elements", "3 3 1 3", "3 300000000 1 3"));
  expect_input_error([&] { load(path); }, {"$Elements: claims 300000000 elements"});
}

// Found by the fuzz harness (tests/fuzz/): gmsh 4.8 crashed (SIGSEGV) on a node tag of -1 or -5
// in format 4.1, where it says "Unknown node" for a tag inside the range that no node has.
TEST(MshCounts, ElementNodesOutsideTheNodeTagsAreRefused) {
  TempDir dir;
  const std::string good = read(corner_tet().write(dir, "corner.msh"));
  const std::string path = dir.file("tags.msh");
  for (const std::string tag : {"-5", "-1", "0", "5"}) {
    SCOPED_TRACE(tag);
    write(path, replace_after(good, "$Elements", "3 1 3 2 4", "3 1 3 2 " + tag));
    expect_input_error([&] { load(path); }, {path + ": $Elements: element 3 names node " + tag,
                                             "outside the node tags 1 to 4 of $Nodes", "(line "});
  }
  write(path, replace_after(good, "$Elements", "3 1 3 2 4", "3 1 3 2 18446744073709551615"));
  expect_input_error([&] { load(path); }, {"$Elements: expected an integer for a node tag"});
}

TEST(MshCounts, BinaryAndVersion2FilesAreScannedToo) {
  TempDir dir;
  for (const auto& [format, binary] :
       std::vector<std::pair<double, int>>{{4.1, 1}, {2.2, 0}, {2.2, 1}}) {
    SCOPED_TRACE(std::to_string(format) + (binary ? " binary" : " ASCII"));
    const std::string msh = dir.file("block.msh");
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::open(source_mesh("block.geo"));
    gmsh::model::mesh::generate(3);
    gmsh::option::setNumber("Mesh.MshFileVersion", format);
    gmsh::option::setNumber("Mesh.Binary", binary);
    gmsh::write(msh);
    gmsh::finalize();
    const Mesh m = load(msh);
    EXPECT_EQ(m.num_tets(), load_geo("block.geo", {}).num_tets());
    // The $Nodes count made far larger than the file.
    const std::string text = read(msh);
    const size_t at = text.find("$Nodes\n") + 7;
    std::string bad = text;
    if (format > 4) {  // binary 4.1: four 8-byte counts; the second is the node count
      const uint64_t claim = uint64_t{1} << 30;
      bad.replace(at + 8, 8, reinterpret_cast<const char*>(&claim), 8);
    } else {
      bad.replace(at, text.find('\n', at) - at, "1073741824");
    }
    write(msh, bad);
    expect_input_error([&] { load(msh); }, {"$Nodes: claims 1073741824 nodes"});
  }
}

// gmsh allocated what these counts claim (std::bad_alloc, exit status 4): the entity counts and
// each entity's tag counts of binary format 4.1, and the tags per element of binary format 2.
TEST(MshCounts, BinaryEntityAndTagCountsAreCheckedToo) {
  TempDir dir;
  const auto binary_block = [&](double format) {
    const std::string msh = dir.file("block.msh");
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::open(source_mesh("block.geo"));
    gmsh::model::mesh::generate(3);
    gmsh::option::setNumber("Mesh.MshFileVersion", format);
    gmsh::option::setNumber("Mesh.Binary", 1);
    gmsh::write(msh);
    gmsh::finalize();
    return read(msh);
  };
  const auto claim = [](std::string text, size_t at, auto value) {
    return text.replace(at, sizeof value, reinterpret_cast<const char*>(&value), sizeof value);
  };
  const std::string v41 = binary_block(4.1);
  const size_t entities = v41.find("$Entities\n") + 10;
  const std::string msh = dir.file("bad.msh");
  write(msh, claim(v41, entities, uint64_t{1} << 40));  // the count of points
  expect_input_error([&] { load(msh); }, {msh + ": $Entities: claims 1099511627776 point"});
  write(msh, claim(v41, entities + 32 + 4 + 24, uint64_t{1} << 40));  // the first point's tags
  expect_input_error([&] { load(msh); }, {"$Entities: claims 1099511627776 physical tags"});

  const std::string v22 = binary_block(2.2);
  const size_t elements = v22.find('\n', v22.find("$Elements\n") + 10) + 1;
  write(msh, claim(v22, elements + 8, int32_t{1} << 30));  // tags per element, first block
  expect_input_error([&] { load(msh); }, {msh + ": $Elements: claims", "elements in a block"});
  write(msh, v22);
  EXPECT_GT(load(msh).num_tets(), 0);
}

TEST(MeshCoordinates, NanInfiniteAndOverflowingAreRefusedNamingTheNode) {
  TempDir dir;
  const std::string good = read(corner_tet().write(dir, "corner.msh"));
  const std::string path = dir.file("bad.msh");
  for (const std::string& value : {"nan", "inf", "1e999"}) {
    SCOPED_TRACE(value);
    write(path, replace_after(good, "$Nodes", "\n1 0 0\n", "\n" + value + " 0 0\n"));
    expect_input_error([&] { load(path); }, {path + ": node 2 at (", "not a finite number"});
  }
}

// ---- 4. Bad elements and nodes, named; units ------------------------------------------

TEST(BadElements, DegenerateTetrahedronIsNamedByItsTag) {
  TempDir dir;
  MshFile f;
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};  // four points in the plane z = 0
  f.blocks = {{3, 4, {{1, 2, 3, 4}}}};
  const std::string path = f.write(dir, "flat.msh");
  expect_input_error([&] { load(path); }, {path + ": element 1 (vertices (0, 0, 0)", "degenerate"});
}

TEST(BadElements, OverlappingTetrahedraAreRefusedNamingBoth) {
  TempDir dir;
  MshFile f;  // two tetrahedra on the same side of their common face z = 0: one folded over
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.1, 0.1, 0.5}};
  f.blocks = {{3, 4, {{1, 2, 3, 4}, {1, 3, 2, 5}}}};
  const std::string path = f.write(dir, "folded.msh");
  expect_input_error([&] { load(path); }, {path + ": element 1", "and element 2", "overlap"});
  // A third tetrahedron on a face that two already share.
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, -1}, {0.2, 0.2, 2}};
  f.blocks = {{3, 4, {{1, 2, 3, 4}, {1, 3, 2, 5}, {1, 2, 3, 6}}}};
  expect_input_error([&] { load(f.write(dir, "three.msh")); }, {"element 3", "overlap"});
}

TEST(BadElements, InvertedCurvedTetrahedronIsRefused) {
  TempDir dir;
  MshFile f;  // Tet10, gmsh order; the edge node of (0, 1) pulled to 0.9: past 3/4 of the edge
  f.nodes = {{0, 0, 0},     {1, 0, 0},   {0, 1, 0},   {0, 0, 1},     {0.9, 0, 0},
             {0.5, 0.5, 0}, {0, 0.5, 0}, {0, 0, 0.5}, {0, 0.5, 0.5}, {0.5, 0, 0.5}};
  f.blocks = {{3, 11, {{1, 2, 3, 4, 5, 6, 7, 8, 9, 10}}}};
  const std::string path = f.write(dir, "inverted.msh");
  MeshConfig cfg;
  cfg.file = path;
  cfg.order = 2;
  expect_input_error([&] { load_mesh(cfg); },
                     {path + ": element 1", "inverted or curved too strongly"});
  f.nodes[4] = {0.6, 0, 0};  // curved, still valid
  cfg.file = f.write(dir, "curved.msh");
  EXPECT_EQ(load_mesh(cfg).num_tets(), 1);
}

TEST(BadElements, DuplicatedNodesAreRefusedNamingBoth) {
  TempDir dir;
  MshFile f;  // two tetrahedra on either side of z = 0, their base triangles copied, not shared
  f.nodes = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1},
             {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}};
  f.blocks = {{3, 4, {{1, 2, 3, 4}, {5, 7, 6, 8}}}};
  const std::string path = f.write(dir, "crack.msh");
  expect_input_error([&] { load(path); },
                     {path + ": node 1 at (0, 0, 0) and node 5 at (0, 0, 0)", "same place"});
}

TEST(Units, MillimetreMeshDrawsAWarningWithItsBoundingBox) {
  TempDir dir;
  MshFile f = corner_tet();
  for (auto& x : f.nodes)
    for (double& c : x) c *= 150;  // a 15 cm part drawn in millimetres
  const std::string path = f.write(dir, "mm.msh");
  const std::string warning = units_warning(load(path), path);
  EXPECT_NE(warning.find(path + ": the mesh spans 150 m"), std::string::npos) << warning;
  EXPECT_NE(warning.find("[0, 150] x [0, 150] x [0, 150]"), std::string::npos) << warning;
  EXPECT_NE(warning.find("millimetres"), std::string::npos) << warning;
  for (auto& x : f.nodes)
    for (double& c : x) c *= 1e-7;  // 15 micrometres
  EXPECT_NE(units_warning(load(f.write(dir, "tiny.msh")), path).find("1.5e-05 m"),
            std::string::npos);
  EXPECT_EQ(units_warning(load(corner_tet().write(dir, "m.msh")), path), "");
}

}  // namespace test_mesh_untrusted
}  // namespace
}  // namespace hs::test
