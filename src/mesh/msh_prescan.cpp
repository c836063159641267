// prescan_msh: the file is mapped read-only. An ASCII file of format 2 or 4.1 is checked line
// by line (msh_ascii_check.cpp). In the others, the $Nodes and $Elements headers (and, in
// binary format 4.1, each entity block's header, whose count gmsh allocates too) are read and
// every count is compared with the bytes left after it, at the fewest bytes an item can take:
// 8 for a node ("1\n0 0 0\n"), 4 for an element ("1 1\n"), more in binary files.
#include "mesh/msh_prescan.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstring>
#include <map>
#include <string_view>
#include <utility>

#include "common/error.hpp"
#include "mesh/msh_ascii_check.hpp"

namespace hs {
namespace {

// The whole file, mapped read-only (nothing is copied; pages are read as they are touched).
class MappedFile {
 public:
  explicit MappedFile(const std::string& file) {
    const int fd = open(file.c_str(), O_RDONLY);
    if (fd < 0) throw InputError(file + ": cannot open the mesh file (missing or unreadable)");
    struct stat st {};
    if (fstat(fd, &st) == 0 && st.st_size > 0) {
      size_ = static_cast<size_t>(st.st_size);
      void* p = mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
      data_ = p == MAP_FAILED ? nullptr : static_cast<const char*>(p);
    }
    close(fd);
    if (size_ > 0 && !data_) throw InputError(file + ": cannot read the mesh file");
  }
  ~MappedFile() {
    if (data_) munmap(const_cast<char*>(data_), size_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::string_view text() const {
    return data_ ? std::string_view(data_, size_) : std::string_view();
  }

 private:
  const char* data_ = nullptr;
  size_t size_ = 0;
};

class Scanner {
 public:
  Scanner(const std::string& file, std::string_view text) : file_(file), d_(text) {}

  MshCounts run() {
    MshCounts counts;
    size_t at = line_after("$MeshFormat", 0);
    if (at == npos) {
      // gmsh reads a file without $MeshFormat as format 1, whatever its sections.
      if (line_after("$NOD", 0) == npos && line_after("$ELM", 0) == npos)
        fail("$MeshFormat", "the file has no $MeshFormat section (nor $NOD, as in format 1)", 0);
      return v1(counts);
    }
    const size_t format_line = at;
    const std::string_view word = token(at);
    double version = 0;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), version);
    if (word.empty() || error != std::errc() || end != word.data() + word.size())
      fail("$MeshFormat",
           "expected the format's version, got '" + std::string(word.substr(0, 40)) + "'",
           format_line);
    const int64_t file_type = integer(at, "$MeshFormat", "the file type");
    integer(at, "$MeshFormat", "the data size");
    binary_ = file_type != 0;  // as gmsh reads it
    // gmsh reads format 2 (2.1, 2.2) by one grammar and 4.1 and above by another.
    if (!binary_ && (version >= 4.1 || (version > 2 && version < 3)))
      return check_ascii_msh(file_, d_, version);
    if (binary_) {
      at = skip_line(at);
      if (at + 4 <= d_.size()) {
        int32_t one = 0;
        std::memcpy(&one, d_.data() + at, 4);
        swap_ = one != 1;
      }
      if (version >= 4.1) {
        v41_entities();
        return v41_counts(counts);
      }
      if (version >= 4) return counts;  // gmsh reads format 4.0 in ASCII only
    }
    counts = totals(counts, version >= 4 && version < 4.1);
    if (binary_ && version < 3) v2_element_blocks(counts.elements);
    return counts;
  }

 private:
  static constexpr size_t npos = std::string_view::npos;
  static constexpr int64_t kNodeBytes = 8, kElementBytes = 4;
  static constexpr const char* kEntityNames[4] = {"point", "curve", "surface", "volume"};

  [[noreturn]] void fail(const std::string& section, const std::string& reason, size_t at) const {
    throw InputError(file_ + ": " + section + ": " + reason + " (" + where(at) + ")");
  }

  // Line numbers mean nothing in a binary file: there, the byte.
  std::string where(size_t at) const {
    if (binary_) return "byte " + std::to_string(at);
    int64_t line = 1;
    for (size_t k = 0; k < at && k < d_.size(); ++k) line += d_[k] == '\n';
    return "line " + std::to_string(line);
  }

  // The position after the line that holds exactly `marker` (at a line's start), or npos.
  size_t line_after(std::string_view marker, size_t from) const {
    for (size_t p = d_.find(marker, from); p != npos; p = d_.find(marker, p + 1)) {
      const size_t end = p + marker.size();
      if ((p == 0 || d_[p - 1] == '\n') && (end == d_.size() || d_[end] == '\n' || d_[end] == '\r'))
        return skip_line(end);
    }
    return npos;
  }

  size_t skip_line(size_t at) const {
    const size_t nl = d_.find('\n', at);
    return nl == npos ? d_.size() : nl + 1;
  }

  std::string_view token(size_t& at) const {
    while (at < d_.size() && std::isspace(static_cast<unsigned char>(d_[at]))) ++at;
    const size_t start = at;
    while (at < d_.size() && !std::isspace(static_cast<unsigned char>(d_[at]))) ++at;
    return d_.substr(start, at - start);
  }

  int64_t integer(size_t& at, const std::string& section, const std::string& what) const {
    const size_t start = at;
    const std::string_view t = token(at);
    int64_t value = 0;
    const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (t.empty() || error != std::errc() || end != t.data() + t.size())
      fail(section,
           "expected an integer for " + what + ", got '" + std::string(t.substr(0, 40)) + "'",
           start);
    return value;
  }

  // `count` items of at least `bytes` each must fit in what follows `at`.
  void check_count(int64_t count, int64_t bytes, size_t at, const std::string& section,
                   const std::string& what, size_t reported_at) const {
    const int64_t left = static_cast<int64_t>(d_.size() - std::min(at, d_.size()));
    const std::string problem =
        msh_count_problem(count, bytes, left, static_cast<int64_t>(d_.size()), what);
    if (!problem.empty()) fail(section, problem, reported_at);
  }

  // Binary format 2, ASCII formats 2.0, 3 and 4.0: the header's count only.
  MshCounts totals(MshCounts counts, bool v40) {
    for (const bool nodes : {true, false}) {
      const std::string section = nodes ? "$Nodes" : "$Elements";
      size_t at = line_after(section, 0);
      if (at == npos) continue;
      const size_t header = at;
      if (v40) integer(at, section, "the entity block count");
      const int64_t count = integer(at, section, nodes ? "the node count" : "the element count");
      check_count(count, nodes ? kNodeBytes : kElementBytes, at, section,
                  nodes ? "nodes" : "elements", header);
      (nodes ? counts.nodes : counts.elements) = count;
    }
    return counts;
  }

  MshCounts v1(MshCounts counts) {
    for (const bool nodes : {true, false}) {
      const std::string section = nodes ? "$NOD" : "$ELM";
      size_t at = line_after(section, 0);
      if (at == npos) continue;
      const size_t header = at;
      const int64_t count = integer(at, section, nodes ? "the node count" : "the element count");
      check_count(count, nodes ? kNodeBytes : kElementBytes, at, section,
                  nodes ? "nodes" : "elements", header);
      (nodes ? counts.nodes : counts.elements) = count;
    }
    return counts;
  }

  // Binary values of the file's byte order.
  template <typename T>
  T read_binary(size_t& at, const std::string& section) const {
    if (at + sizeof(T) > d_.size()) fail(section, "the file ends inside a block header", at);
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, d_.data() + at, sizeof(T));
    if (swap_)
      for (size_t k = 0; k < sizeof(T) / 2; ++k) std::swap(bytes[k], bytes[sizeof(T) - 1 - k]);
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    at += sizeof(T);
    return value;
  }

  int64_t count_at(size_t& at, const std::string& section) {
    const uint64_t v = read_binary<uint64_t>(at, section);
    return v > static_cast<uint64_t>(INT64_MAX) ? -1 : static_cast<int64_t>(v);
  }

  // Binary format 4.1's $Entities: four counts, then each entity with its counts of physical
  // tags and bounding entities, each of which gmsh allocates before it reads the items.
  void v41_entities() {
    const std::string section = "$Entities";
    size_t at = line_after(section, 0);
    if (at == npos) return;
    const size_t header = at;
    int64_t count[4];
    for (int64_t& c : count) c = count_at(at, section);
    for (int dim = 0; dim < 4; ++dim) {
      // A point: its tag, 3 coordinates, a tag count; the others: a tag, a box, two counts.
      const int64_t bytes = dim == 0 ? 4 + 24 + 8 : 4 + 48 + 16;
      check_count(count[dim], bytes, at, section, std::string(kEntityNames[dim]) + " entities",
                  header);
      for (int64_t e = 0; e < count[dim]; ++e) {
        const size_t entity = at;
        at += dim == 0 ? 4 + 24 : 4 + 48;
        for (int list = 0; list < (dim == 0 ? 1 : 2); ++list) {
          const int64_t n = count_at(at, section);
          check_count(n, 4, at, section, list == 0 ? "physical tags" : "bounding entities", entity);
          at += static_cast<size_t>(n) * 4;
        }
      }
    }
  }

  // Binary format 2's $Elements after its count line: blocks of a header (type, elements that
  // follow, tags per element), then each element's number, tags and nodes, 4 bytes each; gmsh
  // allocates for a block's tags and nodes from its header.
  void v2_element_blocks(int64_t total) {
    const std::string section = "$Elements";
    size_t at = line_after(section, 0);
    if (at == npos) return;
    at = skip_line(at);
    for (int64_t seen = 0; seen < total;) {
      const size_t block = at;
      const int64_t type = read_binary<int32_t>(at, section);
      const int64_t follow = read_binary<int32_t>(at, section);
      const int64_t tags = read_binary<int32_t>(at, section);
      const int n = msh_element_nodes(type);
      if (n < 0)
        fail(section, "element type " + std::to_string(type) + " is not known to hydrosoft", block);
      if (tags < 0 || follow < 1 || follow > total - seen)
        fail(section,
             "a block header claims " + std::to_string(follow) + " elements of " +
                 std::to_string(tags) + " tags (the section holds " + std::to_string(total) + ")",
             block);
      check_count(follow, 4 * (1 + tags + n), at, section, "elements in a block", block);
      at += static_cast<size_t>(follow * 4 * (1 + tags + n));
      seen += follow;
    }
  }

  MshCounts v41_counts(MshCounts counts) {
    counts.nodes = v41_section(true, counts.tets);
    counts.elements = v41_section(false, counts.tets);
    return counts;
  }

  // One $Nodes or $Elements section of binary format 4.1: the header, then each block's
  // header, each block's data skipped; returns the header's count. Counts tetrahedra into
  // `tets`.
  int64_t v41_section(bool nodes, int64_t& tets) {
    const std::string section = nodes ? "$Nodes" : "$Elements";
    const std::string what = nodes ? "nodes" : "elements";
    size_t at = line_after(section, 0);
    if (at == npos) return 0;
    const size_t header = at;
    const int64_t blocks = count_at(at, section);
    const int64_t total = count_at(at, section);
    const int64_t smallest_tag = count_at(at, section);
    const int64_t largest_tag = count_at(at, section);
    if (nodes) node_tags_ = {smallest_tag, largest_tag};
    const int64_t item_bytes = nodes ? 32 : 16;
    check_count(blocks, 20, at, section, "entity blocks", header);
    check_count(total, item_bytes, at, section, what, header);
    if (!nodes) tets = 0;
    int64_t sum = 0;
    for (int64_t b = 0; b < blocks; ++b) {
      const size_t block = at;
      const int64_t dim = read_binary<int32_t>(at, section);
      read_binary<int32_t>(at, section);                       // the entity's tag
      const int64_t kind = read_binary<int32_t>(at, section);  // parametric, or element type
      const int64_t count = count_at(at, section);
      check_count(count, item_bytes, at, section,
                  what + " in entity block " + std::to_string(b + 1), block);
      sum += count;
      if (sum > total)
        fail(section,
             "the entity blocks hold more " + what + " than the header's " + std::to_string(total),
             block);
      if (nodes) {
        const int64_t per_node = 3 + (kind != 0 ? std::max<int64_t>(dim, 0) : 0);
        at = std::min(d_.size(), at + static_cast<size_t>(count * (1 + per_node)) * 8);
      } else {
        if (kind == 4 || kind == 11) tets += count;
        skip_elements(at, section, kind, count, block);
      }
    }
    if (sum != total)
      fail(section,
           "the entity blocks hold " + std::to_string(sum) + " " + what + ", the header says " +
               std::to_string(total),
           header);
    return total;
  }

  // A node tag of an element outside the $Nodes header's range: gmsh 4.8 looks such a tag up
  // past the end of its table (a tag of -1 read as 2^64 - 1 crashed it) instead of saying
  // "Unknown node" as it does for a tag inside the range that no node has.
  void check_node_tag(int64_t tag, int64_t element, size_t at) const {
    if (tag < std::max<int64_t>(node_tags_.first, 1) || tag > node_tags_.second)
      fail("$Elements",
           "element " + std::to_string(element) + " names node " + std::to_string(tag) +
               ", outside the node tags " + std::to_string(node_tags_.first) + " to " +
               std::to_string(node_tags_.second) + " of $Nodes",
           at);
  }

  // An element's tag, then its nodes: 1 + n 8-byte values; the node tags are checked against
  // the range of $Nodes.
  void skip_elements(size_t& at, const std::string& section, int64_t type, int64_t count,
                     size_t block) const {
    const int n = msh_element_nodes(type);
    if (n < 0)
      fail(section, "element type " + std::to_string(type) + " is not known to hydrosoft", block);
    const int64_t left = static_cast<int64_t>(d_.size() - std::min(at, d_.size()));
    if (count > left / (8 * (1 + n)))
      fail(section,
           "an entity block claims " + std::to_string(count) + " elements of " + std::to_string(n) +
               " nodes, more than the rest of the file can hold",
           block);
    for (int64_t k = 0; k < count; ++k) {
      const size_t start = at;
      const auto element = static_cast<int64_t>(read_binary<uint64_t>(at, section));
      for (int j = 0; j < n; ++j) {
        const uint64_t tag = read_binary<uint64_t>(at, section);
        check_node_tag(tag > static_cast<uint64_t>(INT64_MAX) ? -1 : static_cast<int64_t>(tag),
                       element, start);
      }
    }
  }

  const std::string& file_;
  std::string_view d_;
  bool binary_ = false, swap_ = false;
  std::pair<int64_t, int64_t> node_tags_{1, INT64_MAX};  // the smallest and largest of $Nodes
};

}  // namespace

MshCounts prescan_msh(const std::string& file) {
  const MappedFile mapped(file);
  return Scanner(file, mapped.text()).run();
}

}  // namespace hs
