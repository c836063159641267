// The key registry (deck/deck_keys.hpp) against what it drives: docs/decks.md's key tables are
// its tables, and every shipped deck prints to a deck that reads back to the same printout
// and fingerprint, with every key the deck gave.
//
// After changing a key, rewrite the docs' tables with
//   HYDROSOFT_WRITE_DOCS=1 build/tests/test_deck --gtest_filter='DeckKeys.Docs*'
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../app/text_file.hpp"
#include "deck/config_fingerprint.hpp"
#include "deck/deck.hpp"
#include "deck/deck_keys.hpp"
#include "temp_folder.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;
using testing::TempFolder;

// Markers open a line (the prose may quote them).
const std::string kOpen = "\n<!-- keys:", kClose = "\n<!-- /keys -->";

// docs/decks.md with each marked table replaced by the registry's; `seen` gets the names of
// the marked tables, in the docs' order, and `differ` those whose text was not the registry's.
std::string with_generated_tables(const std::string& doc, std::vector<std::string>& seen,
                                  std::vector<std::string>& differ) {
  std::string out;
  size_t at = 0;
  for (size_t open = doc.find(kOpen); open != std::string::npos; open = doc.find(kOpen, at)) {
    const size_t name_end = doc.find(" -->\n", open);
    const size_t close = doc.find(kClose, name_end);
    if (name_end == std::string::npos || close == std::string::npos) {
      ADD_FAILURE() << "unclosed marker at " << open;
      return doc;
    }
    const std::string name = doc.substr(open + kOpen.size(), name_end - open - kOpen.size());
    seen.push_back(name);
    std::string table;
    for (const auto& t : deck_key_tables())
      if (t.name == name) table = t.markdown;
    EXPECT_FALSE(table.empty()) << "docs/decks.md marks a table '" << name
                                << "' that the registry does not have";
    const size_t begin = name_end + 5, end = close + 1;  // the table's lines, each with its \n
    if (doc.substr(begin, end - begin) != table) {
      differ.push_back(name);
      ADD_FAILURE() << "docs/decks.md's table '" << name << "' is\n"
                    << doc.substr(begin, end - begin) << "the registry's is\n"
                    << table;
    }
    out += doc.substr(at, begin - at) + table;
    at = end;
  }
  return out + doc.substr(at);
}

TEST(DeckKeys, DocsTablesAreTheRegistrys) {
  const fs::path path = fs::path(HYDROSOFT_SOURCE_DIR) / "docs" / "decks.md";
  const std::string doc = testing::text_of(path.string());
  std::vector<std::string> seen, differ;
  const std::string generated = with_generated_tables(doc, seen, differ);
  if (std::getenv("HYDROSOFT_WRITE_DOCS") && generated != doc) std::ofstream(path) << generated;
  EXPECT_TRUE(differ.empty()) << "rewrite docs/decks.md's tables with HYDROSOFT_WRITE_DOCS=1 "
                                 "(see the top of tests/deck/test_deck_keys.cpp)";
  std::vector<std::string> names;
  for (const auto& t : deck_key_tables()) names.push_back(t.name);
  EXPECT_EQ(seen, names) << "every table of the registry is marked once, in its order";
}

// A table's rows as the registry writes them: the type from the value's limits, the default
// from config.hpp, the conditions of use before the meaning.
TEST(DeckKeys, TableRowsComeFromTheDeclarations) {
  std::string time;
  for (const auto& t : deck_key_tables())
    if (t.name == "time") time = t.markdown;
  EXPECT_NE(time.find("| `steps` | integer ≥ 1 | 1 | static/quasi-static: number of load"),
            std::string::npos)
      << time;
  EXPECT_NE(time.find("| `dt` | number > 0 | required if dynamic | dynamic: time step (s)"),
            std::string::npos)
      << time;
  EXPECT_NE(time.find("| `max_cutbacks` | integer ≥ 0 | 8 |"), std::string::npos) << time;
}

// The keys a YAML tree gives, as dotted paths (list entries by index).
void key_paths(const YAML::Node& node, const std::string& path, std::vector<std::string>& out) {
  if (node.IsMap()) {
    for (const auto& entry : node) {
      const std::string key = child_key(path, entry.first.Scalar());
      out.push_back(key);
      key_paths(entry.second, key, out);
    }
  } else if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i) key_paths(node[i], item_key(path, i), out);
  }
}

bool has_path(const YAML::Node& root, const std::string& path) {
  std::vector<std::string> all;
  key_paths(root, "", all);
  return std::find(all.begin(), all.end(), path) != all.end();
}

// Every deck of input/: its printout is a deck; read back, it prints the same text (but for
// the "# deck:" line) and has the same fingerprint (the restart's check); and every key the
// deck gives is in the printout (a key the printout dropped would read back as its default).
TEST(DeckKeys, ShippedDecksRoundTripThroughThePrintout) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(HYDROSOFT_SOURCE_DIR) / "input")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    const Config first = parse_deck(entry.path().string());
    const std::string printed = format_config(first);
    TempFolder tmp;
    // Elsewhere: the printed mesh path is absolute, so the copy reads the same mesh.
    const Config second = parse_deck(tmp.write(entry.path().filename().string(), printed));
    const std::string again = format_config(second);
    EXPECT_EQ(again.substr(again.find('\n')), printed.substr(printed.find('\n')));
    EXPECT_EQ(config_fingerprint(first), config_fingerprint(second));
    const YAML::Node given = YAML::LoadFile(entry.path().string());
    const YAML::Node reprinted = YAML::Load(printed);
    std::vector<std::string> paths;
    key_paths(given, "", paths);
    for (const std::string& path : paths)
      EXPECT_TRUE(has_path(reprinted, path)) << path << " is not in the printout:\n" << printed;
    ++count;
  }
  EXPECT_GE(count, 16);
}

}  // namespace
}  // namespace hs
