// The line-by-line check of ASCII .msh files of formats 2.2 and 4.1 (src/mesh/msh_ascii_check.hpp):
// the fuzz harness's crashes of gmsh, refused naming the line; every line of two small files
// deleted, doubled, a field short or long or not a number, refused naming a line; the files
// gmsh writes still read, their tetrahedra counted as gmsh counts them. Every file is written
// by the test into a temporary folder that the test removes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "mesh/msh_prescan.hpp"
#include "mesh_test_util.hpp"

namespace hs::test {
namespace {
namespace test_msh_structure {

namespace fs = std::filesystem;

std::string write(const TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = dir.file(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

Mesh load(const std::string& file, int order = 1) {
  MeshConfig cfg;
  cfg.file = file;
  cfg.order = order;
  return load_mesh(cfg);
}

// Found by the fuzz harness (10,000 cases): each crashed gmsh 4.8 (SIGSEGV) inside
// `hydrosoft --check`. Cut down to a tetrahedron or two; each still crashed it.
// $PhysicalNames' count line doubled (formats 4.1 and 4.1 P2): gmsh read the second "4" as
// a name's dimension and indexed its table of four dimensions with it.
const char* const kCountLineDoubled =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
    "$PhysicalNames\n4\n4\n2 2 \"bottom\"\n2 3 \"top\"\n3 1 \"body\"\n$EndPhysicalNames\n"
    "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
    "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n";
// Format 2.2, node 4's line short of a coordinate: gmsh read node 5's tag as node 4's z and
// "0.5" as a node 0, and crashed on the element that names node 5.
const char* const kNodeLineShort =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
    "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 1\n5 0.5 0.5 -1\n$EndNodes\n"
    "$Elements\n2\n1 4 2 1 1 1 2 3 4\n2 4 2 1 1 1 3 2 5\n$EndElements\n";

TEST(MshStructure, FuzzCrashesOfGmshAreRefusedNamingTheLine) {
  TempDir dir;
  const std::string a = write(dir, "names.msh", kCountLineDoubled);
  expect_input_error([&] { load(a); },
                     {a + ": $PhysicalNames: '4' is not a name's line: dim tag \"name\" (line 6)"});
  const std::string b = write(dir, "short.msh", kNodeLineShort);
  expect_input_error([&] { load(b); }, {b + ": $Nodes: '4 0 1' has 3 fields where a node's line "
                                            "(tag x y z) has 4 (line 9)"});
}

// The corner tetrahedron in format 4.1 (with $PhysicalNames and $Entities) and 2.2.
const char* const kCorner41 =
    "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
    "$PhysicalNames\n2\n2 2 \"bottom\"\n3 1 \"body\"\n$EndPhysicalNames\n"
    "$Entities\n0 0 1 1\n"
    "1 0 0 0 1 1 0 1 2 0 \n"
    "1 0 0 0 1 1 1 1 1 1 1 \n$EndEntities\n"
    "$Nodes\n2 4 1 4\n2 1 0 3\n1\n2\n3\n0 0 0\n1 0 0\n0 1 0\n3 1 0 1\n4\n0 0 1\n$EndNodes\n"
    "$Elements\n2 2 1 2\n2 1 2 1\n1 1 3 2\n3 1 4 1\n2 1 2 3 4\n$EndElements\n";
const char* const kCorner22 =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
    "$PhysicalNames\n2\n2 2 \"bottom\"\n3 1 \"body\"\n$EndPhysicalNames\n"
    "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
    "$Elements\n2\n1 2 2 2 1 1 3 2\n2 4 2 1 1 1 2 3 4\n$EndElements\n";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const auto& l : lines) text += l + "\n";
  return text;
}

// The mutations of line n that the fuzz family makes: (what, new text).
std::vector<std::pair<std::string, std::string>> mutations(const std::vector<std::string>& lines,
                                                           size_t n) {
  std::vector<std::pair<std::string, std::string>> out;
  auto with = [&](const std::string& line) {
    auto copy = lines;
    copy[n] = line;
    return joined(copy);
  };
  auto without = lines;
  without.erase(without.begin() + static_cast<long>(n));
  out.push_back({"deleted", joined(without)});
  auto doubled = lines;
  doubled.insert(doubled.begin() + static_cast<long>(n), lines[n]);
  out.push_back({"doubled", joined(doubled)});
  std::vector<std::string> words;
  std::istringstream in(lines[n]);
  for (std::string w; in >> w;) words.push_back(w);
  auto words_line = [](const std::vector<std::string>& w) {
    std::string s;
    for (const auto& x : w) s += (s.empty() ? "" : " ") + x;
    return s;
  };
  out.push_back({"a field added", with(words_line(words) + " 7")});
  if (words.size() > 1 || lines[n][0] != '$') {
    auto last = words, first = words;
    last.pop_back();
    first.erase(first.begin());
    out.push_back({"its last field dropped", with(words_line(last))});
    out.push_back({"its first field dropped", with(words_line(first))});
    for (size_t k = 0; k < words.size(); ++k) {
      auto x = words;
      x[k] = "x";
      out.push_back({"field " + std::to_string(k + 1) + " made 'x'", with(words_line(x))});
    }
  }
  return out;
}

// Each mutation of each line is refused before gmsh runs, in one line that names the file,
// the section and a line; the unchanged files read, their tetrahedron counted.
TEST(MshStructure, EveryLineDeletedDoubledShortLongOrNotANumberIsRefused) {
  TempDir dir;
  for (const char* base : {kCorner41, kCorner22}) {
    const std::string good = write(dir, "good.msh", base);
    EXPECT_EQ(prescan_msh(good).tets, 1);
    EXPECT_EQ(load(good).num_tets(), 1);
    const auto lines = lines_of(base);
    int refused = 0, cases = 0;
    for (size_t n = 0; n < lines.size(); ++n)
      for (const auto& [what, text] : mutations(lines, n)) {
        ++cases;
        SCOPED_TRACE(std::string(lines[1]) + ": line " + std::to_string(n + 1) + " '" + lines[n] +
                     "' " + what);
        const std::string path = write(dir, "bad.msh", text);
        try {
          prescan_msh(path);
          ADD_FAILURE() << "accepted";
        } catch (const InputError& e) {
          const std::string m = e.what();
          EXPECT_EQ(m.rfind(path + ": $", 0), 0u) << m;
          EXPECT_NE(m.find(" (line "), std::string::npos) << m;
          EXPECT_EQ(m.find('\n'), std::string::npos) << m;
          ++refused;
        }
      }
    EXPECT_EQ(refused, cases);
    EXPECT_GT(cases, 6 * static_cast<int>(lines.size()));
  }
}

TEST(MshStructure, TheReasonNamesWhatIsWrongAndWhere) {
  TempDir dir;
  const std::string path = dir.file("case.msh");
  const std::string good41 = kCorner41;
  auto refused = [&](const std::string& text, const std::vector<std::string>& parts) {
    std::ofstream(path, std::ios::binary) << text;
    expect_input_error([&] { prescan_msh(path); }, parts);
  };
  auto edit = [](std::string text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  refused(edit(good41, "2 2 \"bottom\"", "7 2 \"bottom\""),
          {"$PhysicalNames: the dimension 7 of '7 2 \"bottom\"' is not 0, 1, 2 or 3 (line 6)"});
  refused(edit(good41, "2 2 \"bottom\"", "2 2 bottom"), {"is not a name's line", "(line 6)"});
  refused(edit(good41, "\"body\"", "\"" + std::string(300, 'g') + "\""),
          {"a physical name of 300 characters; at most 250 (line 7)"});
  refused(edit(good41, "1 0 0 0 1 1 0 1 2 0 \n", "1 0 0 0 1 1 0 1 2 0 9\n"),
          {"$Entities: '1 0 0 0 1 1 0 1 2 0 9' has 11 fields where its counts make 10 (line 11)"});
  refused(edit(good41, "0 1 0\n3 1 0 1", "0 1 x\n3 1 0 1"),
          {"$Nodes: expected a number for a coordinate, got 'x' (line 22)"});
  refused(edit(good41, "2 1 2 3 4\n", "2 1 2 3 4 4\n"),
          {"$Elements: '2 1 2 3 4 4' has 6 fields where an element's line (tag and nodes) has 5"});
  refused(edit(good41, "3 1 4 1\n", "3 1 4 2\n"),
          {"$Elements: the entity blocks hold more elements than the header's 2 (line 31)"});
  refused(
      edit(good41, "2 1 2 3 4\n", ""),
      {"found '$EndElements' where an element's line (tag and nodes) should come", "(line 32)"});
  refused(edit(good41, "$EndNodes\n", ""), {"$Nodes: expected $EndNodes, found '$Elements'"});
  refused(edit(good41, "1 0 0\n0 1 0", "1 0 0\n0 1 0\n0 0 0"),
          {"$Nodes: '0 0 0' has 3 fields where an entity block's header (dim tag parametric "
           "count) has 4 (line 23)"});
  refused(edit(good41, "$Nodes\n", "$NodesX\n"), {"gmsh would read this section as $Nodes"});
  refused(edit(good41, "$Nodes\n2 4 1 4", "2 4 1 4"),
          {"$EndEntities: expected a section ($Name) after it, found '2 4 1 4' (line 14)"});
  refused(edit(good41, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n", "") + "$MeshFormat\n4.1 0 8\n",
          {"$MeshFormat: the file must start with it, found '$PhysicalNames' (line 1)"});
  refused(edit(good41, "2 1 2 3 4\n", "2 1 2 3 5\n"),
          {"$Elements: element 2 names node 5, outside the node tags 1 to 4 of $Nodes"});
  refused(edit(kCorner22, "4 0 0 1\n", "4 0 0 1\n5 0 0 2\n"),
          {"$Nodes: expected $EndNodes, found '5 0 0 2': the section holds more lines than its "
           "counts say (line 15)"});
  refused(edit(kCorner22, "2 4 2 1 1", "2 4 3 1 1"),
          {"$Elements: '2 4 3 1 1 1 2 3 4' has 9 fields where an element of 4 nodes and 3 tags "
           "has 10 (line 19)"});
  refused(edit(kCorner22, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n", ""),
          {"$MeshFormat: the file has no $MeshFormat section", "(line 1)"});
  refused(edit(kCorner22, "2 4 2 1 1", "2 99 2 1 1"),
          {"$Elements: element type 99 is not known to hydrosoft (line 19)"});
}

// What gmsh writes, and what its reader takes that a writer might put: CRLF line ends, blank
// lines between sections, unknown sections, numbers with a sign, in hexadecimal, inf and nan
// (refused later naming the node), 0-based node tags in format 2.2.
TEST(MshStructure, WhatGmshWritesAndReadsIsAccepted) {
  TempDir dir;
  for (const auto& [name, order] : std::vector<std::pair<std::string, int>>{
           {"block_v41", 1}, {"block_v22", 1}, {"block_v41_p2", 2}}) {
    SCOPED_TRACE(name);
    const std::string path =
        std::string(HYDROSOFT_SOURCE_DIR) + "/tests/fuzz/base_meshes/" + name + ".msh";
    const MshCounts counts = prescan_msh(path);
    const Mesh m = load(path, order);
    EXPECT_EQ(counts.tets, m.num_tets());  // as gmsh read them
    EXPECT_EQ(counts.nodes, order == 2 ? 232 : 45);
  }
  std::string crlf;
  for (const char c : std::string(kCorner41))
    crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  EXPECT_EQ(load(write(dir, "crlf.msh", crlf)).num_tets(), 1);
  std::string extra = kCorner41;
  extra.insert(extra.find("$Nodes"), "\n$Comments\nmade by hand\n$EndComments\n\n");
  extra.replace(extra.find("0 1 0\n3 1"), 5, "+0 0x1p0 0.0");
  EXPECT_EQ(load(write(dir, "extra.msh", extra)).num_tets(), 1);
  std::string zero = kCorner22;
  for (const char* tag : {"4 0 0 1", "3 0 1 0", "2 1 0 0", "1 0 0 0"}) {
    const size_t at = zero.find(tag);
    zero[at] = static_cast<char>(zero[at] - 1);
  }
  zero.replace(zero.find("1 2 2 2 1 1 3 2"), 15, "1 2 2 2 1 0 2 1");
  zero.replace(zero.find("2 4 2 1 1 1 2 3 4"), 17, "2 4 2 1 1 0 1 2 3");
  EXPECT_EQ(prescan_msh(write(dir, "zero.msh", zero)).tets, 1);
  std::string nan = kCorner41;
  nan.replace(nan.find("0 0 1\n$EndNodes"), 5, "nan 0 inf");
  expect_input_error([&] { load(write(dir, "nan.msh", nan)); },
                     {"node 4 at (", "not a finite number"});
}

}  // namespace test_msh_structure
}  // namespace
}  // namespace hs::test
