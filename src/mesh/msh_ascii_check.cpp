// check_ascii_msh: one pass over the lines. Each section that gmsh parses is read by the
// format's grammar: the count line, then exactly as many lines as it says, each with its
// number of fields, then the section's end. The other sections are skipped to their end.
// Messages are built only when a line fails; the file is never copied, and nothing that is
// allocated grows with it.
#include "mesh/msh_ascii_check.hpp"

#include <algorithm>
#include <climits>
#include <map>

#include "common/error.hpp"
#include "mesh/msh_text.hpp"

namespace hs {

int msh_element_nodes(int64_t type) {
  static const std::map<int64_t, int> kNodes = {
      {1, 2},   {2, 3},   {3, 4},   {4, 4},   {5, 8},   {6, 6},   {7, 5},   {8, 3},   {9, 6},
      {10, 9},  {11, 10}, {12, 27}, {13, 18}, {14, 14}, {15, 1},  {16, 8},  {17, 20}, {18, 15},
      {19, 13}, {20, 9},  {21, 10}, {22, 12}, {23, 15}, {24, 15}, {25, 21}, {26, 4},  {27, 5},
      {28, 6},  {29, 20}, {30, 35}, {31, 56}, {92, 64}, {93, 125}};
  const auto it = kNodes.find(type);
  return it == kNodes.end() ? -1 : it->second;
}

std::string msh_count_problem(int64_t count, int64_t bytes, int64_t left, int64_t size,
                              const std::string& what) {
  if (count < 0)
    return "claims " + std::to_string(count) + " " + what + ": a count cannot be negative";
  if (count <= left / bytes) return "";
  return "claims " + std::to_string(count) + " " + what + ", more than the " +
         std::to_string(size) + "-byte file can hold (at most " + std::to_string(left / bytes) +
         " in the " + std::to_string(left) + " bytes after it)";
}

namespace {

using namespace msh_text;

class Checker {
 public:
  Checker(const std::string& file, std::string_view text, double version)
      : file_(file), lines_(text), v4_(version >= 4.1) {}

  MshCounts run() {
    std::string last = "the start of the file";  // where a line between sections follows
    while (lines_.next()) {
      const std::string_view line = trim_end(lines_.line());
      if (line.empty()) continue;
      if (line[0] != '$') fail(last, "expected a section ($Name) after it, found " + shown(line));
      const std::string_view name = line.substr(1);
      if (name.rfind("End", 0) == 0) fail(last, shown(line) + " ends no section that is open");
      if (!seen_format_ && name != "MeshFormat")
        fail("$MeshFormat", "the file must start with it, found " + shown(line));
      section(name);
      last = "$End" + std::string(name);
    }
    return counts_;
  }

 private:
  [[noreturn]] void fail(std::string_view section, const std::string& reason) const {
    fail_at(section, reason, lines_.number());
  }
  [[noreturn]] void fail_at(std::string_view section, const std::string& reason,
                            int64_t line) const {
    throw InputError(file_ + ": " + std::string(section) + ": " + reason + " (line " +
                     std::to_string(line) + ")");
  }

  // The sections gmsh parses are checked; gmsh picks them by the start of their name, so
  // "$NodesX" (or "$NOD" in format 2) would be read as $Nodes: such a name is refused.
  void section(std::string_view name) {
    static const std::string_view kChecked[] = {"MeshFormat", "PhysicalNames", "Entities", "Nodes",
                                                "Elements"};
    for (int k = 0; k < 5; ++k) {
      const std::string_view known = kChecked[k];
      if (name == known) {
        if (seen_ & (1 << k))
          fail("$" + std::string(name), "a second $" + std::string(name) + " section");
        seen_ |= 1 << k;
        if (known == "MeshFormat") return mesh_format();
        if (known == "PhysicalNames") return physical_names();
        if (known == "Entities") return v4_ ? entities() : skip(name);
        if (known == "Nodes") return v4_ ? nodes41() : nodes2();
        return v4_ ? elements41() : elements2();
      }
      const bool v2_alias =
          !v4_ && ((known == "Nodes" &&
                    (name.rfind("NO", 0) == 0 || name.rfind("ParametricNodes", 0) == 0)) ||
                   (known == "Elements" && name.rfind("ELM", 0) == 0));
      if (name.rfind(known, 0) == 0 || v2_alias)
        fail("$" + std::string(name), "gmsh would read this section as $" + std::string(known) +
                                          "; hydrosoft reads the sections by their exact names");
    }
    skip(name);
  }

  void skip(std::string_view name) {
    while (lines_.next()) {
      const std::string_view line = trim_end(lines_.line());
      if (line.size() == name.size() + 4 && line.rfind("$End", 0) == 0 && line.substr(4) == name)
        return;
    }
    fail("$" + std::string(name), "the file ends before $End" + std::string(name));
  }

  // The next line inside `section`, where `what` comes.
  std::string_view data_line(std::string_view section, const char* what) {
    if (!lines_.next()) fail(section, std::string("the file ends where ") + what + " should come");
    const std::string_view line = lines_.line();
    if (!line.empty() && line[0] == '$')
      fail(section, "found " + shown(line) + " where " + what +
                        " should come: the section holds fewer lines than its counts say");
    return line;
  }

  // Format 4.1: the entity blocks' counts add up to the section header's total.
  void block_sum_matches(std::string_view section, int64_t sum, int64_t total, const char* what,
                         int64_t header) {
    if (sum != total)
      fail_at(section,
              "the entity blocks hold " + std::to_string(sum) + " " + what + ", the header says " +
                  std::to_string(total),
              header);
  }

  // The section's last line, after as many lines as its counts said.
  void end_of(std::string_view section) {
    const bool more = lines_.next();
    const std::string_view line = more ? trim_end(lines_.line()) : std::string_view();
    if (!more || line.size() != section.size() + 3 || line.rfind("$End", 0) != 0 ||
        line.substr(4) != section.substr(1))
      fail(section, "expected $End" + std::string(section.substr(1)) + ", found " +
                        (more ? shown(line) : "the end of the file") +
                        (more && line.rfind("$", 0) != 0
                             ? ": the section holds more lines than its counts say"
                             : ""));
  }

  // The line must hold `n` fields; `form` says which.
  void expect_fields(std::string_view section, std::string_view line, size_t n,
                     const char* form) const {
    const size_t k = Fields(line).count();
    if (k != n)
      fail(section, shown(line) + " has " + std::to_string(k) + " field" + (k == 1 ? "" : "s") +
                        " where " + form + " has " + std::to_string(n));
  }

  int64_t integer(std::string_view section, Fields& f, const char* what, int64_t lo = INT64_MIN,
                  int64_t hi = INT64_MAX) const {
    const std::string_view t = f.next();
    int64_t value = 0;
    if (!parse_integer(t, value))
      fail(section, std::string("expected an integer for ") + what + ", got " + shown(t));
    if (value < lo || value > hi)
      fail(section, std::string(what) + " " + std::to_string(value) + " is not between " +
                        std::to_string(lo) + " and " + std::to_string(hi));
    return value;
  }

  void reals(std::string_view section, Fields& f, int n, const char* what) const {
    for (int k = 0; k < n; ++k) {
      const std::string_view t = f.next();
      if (!is_real(t))
        fail(section, std::string("expected a number for ") + what + ", got " + shown(t));
    }
  }

  void check_count(std::string_view section, int64_t count, int64_t bytes, const std::string& what,
                   int64_t line) const {
    const std::string problem = msh_count_problem(count, bytes, lines_.left(), lines_.size(), what);
    if (!problem.empty()) fail_at(section, problem, line);
  }

  // A count line of `n` counts, each at least 0.
  template <size_t N>
  void count_line(std::string_view section, const char* form, const char* const (&names)[N],
                  int64_t (&values)[N]) {
    const std::string_view line = data_line(section, form);
    expect_fields(section, line, N, form);
    Fields f(line);
    for (size_t k = 0; k < N; ++k) values[k] = integer(section, f, names[k]);
  }

  void mesh_format() {
    constexpr std::string_view S = "$MeshFormat";
    const std::string_view line = data_line(S, "the format line (version file-type data-size)");
    expect_fields(S, line, 3, "the format line (version file-type data-size)");
    Fields f(line);
    reals(S, f, 1, "the version");
    integer(S, f, "the file type");
    integer(S, f, "the data size");
    end_of(S);
    seen_format_ = true;
  }

  void physical_names() {
    constexpr std::string_view S = "$PhysicalNames";
    int64_t count[1];
    count_line(S, "the count line (the number of names)", {"the count of names"}, count);
    check_count(S, count[0], 7, "names", lines_.number());  // 0 1 ""
    for (int64_t k = 0; k < count[0]; ++k) {
      const std::string_view line = data_line(S, "a name's line (dim tag \"name\")");
      Fields f(line);
      int64_t dim = 0, tag = 0;
      const std::string_view name = (parse_integer(f.next(), dim) && parse_integer(f.next(), tag))
                                        ? f.rest()
                                        : std::string_view();
      if (name.size() < 2 || name.front() != '"' || name.back() != '"' ||
          name.substr(1, name.size() - 2).find('"') != std::string_view::npos)
        fail(S, shown(line) + " is not a name's line: dim tag \"name\"");
      // gmsh indexes a table of the four dimensions with it (a count line read as a name's
      // line, its dimension 8, crashed gmsh 4.8).
      if (dim < 0 || dim > 3)
        fail(S, "the dimension " + std::to_string(dim) + " of " + shown(line) +
                    " is not 0, 1, 2 or 3");
      if (tag < INT_MIN || tag > INT_MAX)
        fail(S, "the tag of " + shown(line) + " does not fit in 32 bits");
      if (name.size() - 2 > 250)  // gmsh reads 255 bytes of the line: the rest would be misread
        fail(S,
             "a physical name of " + std::to_string(name.size() - 2) + " characters; at most 250");
    }
    end_of(S);
  }

  void entities() {
    constexpr std::string_view S = "$Entities";
    int64_t n[4];
    count_line(S, "the count line (points curves surfaces volumes)",
               {"the count of points", "the count of curves", "the count of surfaces",
                "the count of volumes"},
               n);
    for (int dim = 0; dim < 4; ++dim) {
      check_count(S, n[dim], 10, "entities of dimension " + std::to_string(dim), lines_.number());
      for (int64_t k = 0; k < n[dim]; ++k) {
        const std::string_view line = data_line(S, "an entity's line");
        Fields f(line);
        const int64_t fields = static_cast<int64_t>(f.count());
        integer(S, f, "an entity tag", INT_MIN, INT_MAX);
        reals(S, f, dim == 0 ? 3 : 6,
              dim == 0 ? "a point's coordinates" : "an entity's bounding box");
        int64_t used = dim == 0 ? 4 : 7;
        // Physical tags, then (not for points) bounding entities: a count and its tags.
        for (int list = 0; list < (dim == 0 ? 1 : 2); ++list) {
          const int64_t m = integer(
              S, f, list == 0 ? "the count of physical tags" : "the count of bounding entities", 0,
              fields - used - 1);
          used += 1 + m;
          for (int64_t j = 0; j < m; ++j) integer(S, f, "an entity tag", INT_MIN, INT_MAX);
        }
        if (used != fields)
          fail(S, shown(line) + " has " + std::to_string(fields) +
                      " fields where its counts make " + std::to_string(used));
      }
    }
    end_of(S);
  }

  // Node tags: at least 1 in format 4.1 (0 in format 2, which gmsh takes as 0-based), and
  // within 32 bits, as gmsh 4.8 looks them up.
  void node_tag(std::string_view section, Fields& f) {
    const int64_t tag = integer(section, f, "a node tag", v4_ ? 1 : 0, INT_MAX);
    node_tags_ = {std::min(node_tags_.first, tag), std::max(node_tags_.second, tag)};
  }

  void nodes41() {
    constexpr std::string_view S = "$Nodes";
    const int64_t header = lines_.number() + 1;
    int64_t h[4];
    count_line(S, "the header (blocks nodes smallest-tag largest-tag)",
               {"the entity block count", "the node count", "the smallest tag", "the largest tag"},
               h);
    check_count(S, h[0], 8, "entity blocks", header);
    check_count(S, h[1], 8, "nodes", header);
    int64_t sum = 0;
    for (int64_t b = 0; b < h[0]; ++b) {
      const char* form = "an entity block's header (dim tag parametric count)";
      const std::string_view line = data_line(S, form);
      const int64_t block = lines_.number();
      expect_fields(S, line, 4, form);
      Fields f(line);
      const int64_t dim = integer(S, f, "an entity dimension", 0, 3);
      integer(S, f, "an entity tag", INT_MIN, INT_MAX);
      const int64_t parametric = integer(S, f, "the parametric flag", 0, 1);
      const int64_t count = integer(S, f, "a block's node count");
      check_count(S, count, 8, "nodes in entity block " + std::to_string(b + 1), block);
      if ((sum += count) > h[1])
        fail(S, "the entity blocks hold more nodes than the header's " + std::to_string(h[1]));
      for (int64_t k = 0; k < count; ++k) {
        const std::string_view tag = data_line(S, "a node tag");
        expect_fields(S, tag, 1, "a node tag line");
        Fields t(tag);
        node_tag(S, t);
      }
      const int per_node = 3 + static_cast<int>(parametric ? dim : 0);
      const char* form_xyz = parametric && dim > 0 ? "a node's line (x y z and its parameters)"
                                                   : "a node's line (x y z)";
      for (int64_t k = 0; k < count; ++k) {
        const std::string_view xyz = data_line(S, form_xyz);
        expect_fields(S, xyz, per_node, form_xyz);
        Fields c(xyz);
        reals(S, c, per_node, "a coordinate");
      }
    }
    block_sum_matches(S, sum, h[1], "nodes", header);
    end_of(S);
    counts_.nodes = h[1];
    have_nodes_ = true;
  }

  void nodes2() {
    constexpr std::string_view S = "$Nodes";
    int64_t count[1];
    count_line(S, "the count line (the number of nodes)", {"the node count"}, count);
    check_count(S, count[0], 8, "nodes", lines_.number());
    for (int64_t k = 0; k < count[0]; ++k) {
      const std::string_view line = data_line(S, "a node's line (tag x y z)");
      expect_fields(S, line, 4, "a node's line (tag x y z)");
      Fields f(line);
      node_tag(S, f);
      reals(S, f, 3, "a coordinate");
    }
    end_of(S);
    counts_.nodes = count[0];
    have_nodes_ = true;
  }

  // A node of an element: within the tags that $Nodes holds. gmsh 4.8 looks a tag outside
  // them up past the end of its table (a tag of -1 crashed it; in format 2.2, a node line
  // short of a field shifted the tags so that one the elements name was missing).
  void element_node(std::string_view section, Fields& f, int64_t element) const {
    const int64_t tag = integer(section, f, "a node tag");
    if (tag < node_tags_.first || tag > node_tags_.second)
      fail(section, "element " + std::to_string(element) + " names node " + std::to_string(tag) +
                        ", outside the node tags " + std::to_string(node_tags_.first) + " to " +
                        std::to_string(node_tags_.second) + " of $Nodes");
  }

  // The nodes of the element type that comes next on the line; `tet` says whether it is one.
  int element_type(std::string_view section, Fields& f, bool& tet) const {
    const int64_t type = integer(section, f, "an element type");
    const int n = msh_element_nodes(type);
    if (n < 0) fail(section, "element type " + std::to_string(type) + " is not known to hydrosoft");
    tet = type == 4 || type == 11;
    return n;
  }

  void elements41() {
    constexpr std::string_view S = "$Elements";
    if (!have_nodes_) fail(S, "no $Nodes section before it");
    const int64_t header = lines_.number() + 1;
    int64_t h[4];
    count_line(
        S, "the header (blocks elements smallest-tag largest-tag)",
        {"the entity block count", "the element count", "the smallest tag", "the largest tag"}, h);
    check_count(S, h[0], 8, "entity blocks", header);
    check_count(S, h[1], 4, "elements", header);
    int64_t sum = 0;
    counts_.tets = 0;
    for (int64_t b = 0; b < h[0]; ++b) {
      const char* form = "an entity block's header (dim tag type count)";
      const std::string_view line = data_line(S, form);
      const int64_t block = lines_.number();
      expect_fields(S, line, 4, form);
      Fields f(line);
      integer(S, f, "an entity dimension", 0, 3);
      integer(S, f, "an entity tag", INT_MIN, INT_MAX);
      bool tet = false;
      const int n = element_type(S, f, tet);
      const int64_t count = integer(S, f, "a block's element count");
      check_count(S, count, 4, "elements in entity block " + std::to_string(b + 1), block);
      if ((sum += count) > h[1])
        fail(S, "the entity blocks hold more elements than the header's " + std::to_string(h[1]));
      if (tet) counts_.tets += count;
      for (int64_t k = 0; k < count; ++k) {
        const std::string_view element = data_line(S, "an element's line (tag and nodes)");
        expect_fields(S, element, static_cast<size_t>(1 + n), "an element's line (tag and nodes)");
        Fields e(element);
        const int64_t tag = integer(S, e, "an element's tag");
        for (int j = 0; j < n; ++j) element_node(S, e, tag);
      }
    }
    block_sum_matches(S, sum, h[1], "elements", header);
    end_of(S);
    counts_.elements = h[1];
  }

  void elements2() {
    constexpr std::string_view S = "$Elements";
    if (!have_nodes_) fail(S, "no $Nodes section before it");
    int64_t count[1];
    count_line(S, "the count line (the number of elements)", {"the element count"}, count);
    check_count(S, count[0], 4, "elements", lines_.number());
    counts_.tets = 0;
    for (int64_t k = 0; k < count[0]; ++k) {
      const std::string_view line =
          data_line(S, "an element's line (tag type tag-count tags nodes)");
      Fields f(line);
      const int64_t fields = static_cast<int64_t>(f.count());
      const int64_t tag = integer(S, f, "an element's tag", INT_MIN, INT_MAX);
      bool tet = false;
      const int n = element_type(S, f, tet);
      const int64_t tags = integer(S, f, "the count of an element's tags", 0, fields);
      if (fields != 3 + tags + n)
        fail(S, shown(line) + " has " + std::to_string(fields) + " fields where an element of " +
                    std::to_string(n) + " nodes and " + std::to_string(tags) + " tags has " +
                    std::to_string(3 + tags + n));
      for (int64_t j = 0; j < tags; ++j) integer(S, f, "an element's tag", INT_MIN, INT_MAX);
      for (int j = 0; j < n; ++j) element_node(S, f, tag);
      counts_.tets += tet;
    }
    end_of(S);
    counts_.elements = count[0];
  }

  const std::string& file_;
  Lines lines_;
  const bool v4_;
  bool seen_format_ = false, have_nodes_ = false;
  int seen_ = 0;  // a bit for each checked section read
  std::pair<int64_t, int64_t> node_tags_{INT64_MAX, INT64_MIN};  // smallest, largest of $Nodes
  MshCounts counts_;
};

}  // namespace

MshCounts check_ascii_msh(const std::string& file, std::string_view text, double version) {
  return Checker(file, text, version).run();
}

}  // namespace hs
