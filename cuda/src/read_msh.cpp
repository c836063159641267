// Reader for gmsh's ASCII .msh files, versions 4.1 and 2.2: the nodes and the 2D elements.
// Hand-written because this module must build without gmsh (src/mesh/ reads with gmsh itself).
#include <unordered_map>

#include "fluidweight/mesh_io.hpp"
#include "text_reader.hpp"

namespace fluidweight {
namespace {

// Corner count of the 2D element types (first-order corners of higher-order ones); 0: not 2D.
int corners_of(long long type) {
  switch (type) {
    case 2:
    case 9:
    case 20:
    case 21:
      return 3;  // triangles of order 1 to 3
    case 3:
    case 10:
    case 16:
      return 4;  // quadrangles of order 1 and 2
    default:
      return 0;
  }
}

// Nodes per element, for skipping elements that are not 2D (version 2.2 lines).
int nodes_of(long long type) {
  switch (type) {
    case 15:
      return 1;
    case 1:
      return 2;
    case 8:
      return 3;
    case 2:
      return 3;
    case 9:
      return 6;
    case 3:
      return 4;
    case 10:
      return 9;
    case 16:
      return 8;
    case 4:
      return 4;
    case 11:
      return 10;
    case 5:
      return 8;
    case 6:
      return 6;
    case 7:
      return 5;
    case 20:
      return 9;
    case 21:
      return 10;
    default:
      return -1;
  }
}

struct Builder {
  SurfaceMesh mesh;
  std::unordered_map<long long, int> index;  // node tag -> vertex
  void node(detail::TextReader& in, long long tag, double x, double y, double z) {
    if (!index.emplace(tag, mesh.num_vertices()).second) {
      in.fail("node " + std::to_string(tag) + " is defined twice");
    }
    mesh.vertices.insert(mesh.vertices.end(), {x, y, z});
  }
  void element(detail::TextReader& in, long long tag, const std::vector<long long>& nodes,
               int corners) {
    int v[4];
    for (int k = 0; k < corners; ++k) {
      auto it = index.find(nodes[k]);
      if (it == index.end()) {
        in.fail("element " + std::to_string(tag) + " uses node " + std::to_string(nodes[k]) +
                ", which is not defined");
      }
      v[k] = it->second;
    }
    mesh.triangles.insert(mesh.triangles.end(), {v[0], v[1], v[2]});
    if (corners == 4) mesh.triangles.insert(mesh.triangles.end(), {v[0], v[2], v[3]});
  }
};

void expect(detail::TextReader& in, const std::string& word) {
  std::string t = in.token();
  if (t != word) in.fail("expected '" + word + "', got " + detail::quoted(t));
}

void skip_section(detail::TextReader& in, const std::string& name) {
  std::string end = "$End" + name.substr(1);
  while (in.token() != end) {
  }
}

// The fewest bytes an item takes in an ASCII file: a node "1\n0 0 0\n" (tag and coordinates),
// an element its tag and nodes, each a digit and a space, a block header "0 1 0 0\n".
constexpr long long kNodeBytes = 8, kBlockBytes = 8;
long long element_bytes(int nodes) { return 2 * (1 + nodes); }

void read_v41(detail::TextReader& in, Builder& b, bool nodes) {
  const std::string what = nodes ? "nodes" : "elements";
  long long blocks = in.integer("entity block count");
  in.check_count(blocks, kBlockBytes, "entity blocks");
  long long total = in.integer("count");
  in.check_count(total, nodes ? kNodeBytes : element_bytes(1), what);
  in.integer("min tag");
  in.integer("max tag");
  long long sum = 0;
  for (long long k = 0; k < blocks; ++k) {
    if (nodes) {
      in.integer("entity dimension");
      in.integer("entity tag");
      long long parametric = in.integer("parametric flag");
      long long count = in.integer("node count");
      in.check_count(count, kNodeBytes, "nodes in entity block " + std::to_string(k + 1));
      if ((sum += count) > total) {
        in.fail("the entity blocks hold more nodes than the header's " + std::to_string(total));
      }
      std::vector<long long> tags(count);
      for (auto& t : tags) t = in.integer("node tag");
      for (long long t : tags) {
        double x = in.coordinate("x coordinate"), y = in.coordinate("y coordinate"),
               z = in.coordinate("z coordinate");
        if (parametric) in.line();
        b.node(in, t, x, y, z);
      }
    } else {
      in.integer("entity dimension");
      in.integer("entity tag");
      long long type = in.integer("element type");
      long long count = in.integer("element count");
      int n = nodes_of(type);
      if (n < 0) in.fail("element type " + std::to_string(type) + " is not supported");
      in.check_count(count, element_bytes(n), "elements in entity block " + std::to_string(k + 1));
      if ((sum += count) > total) {
        in.fail("the entity blocks hold more elements than the header's " + std::to_string(total));
      }
      std::vector<long long> v(n);
      for (long long e = 0; e < count; ++e) {
        long long tag = in.integer("element tag");
        for (auto& x : v) x = in.integer("node tag");
        if (corners_of(type)) b.element(in, tag, v, corners_of(type));
      }
    }
  }
}

void read_v22(detail::TextReader& in, Builder& b, bool nodes) {
  long long count = in.integer("count");
  in.check_count(count, nodes ? kNodeBytes : element_bytes(1), nodes ? "nodes" : "elements");
  for (long long k = 0; k < count; ++k) {
    if (nodes) {
      long long tag = in.integer("node tag");
      double x = in.coordinate("x coordinate"), y = in.coordinate("y coordinate"),
             z = in.coordinate("z coordinate");
      b.node(in, tag, x, y, z);
    } else {
      long long tag = in.integer("element tag");
      long long type = in.integer("element type");
      long long tags = in.integer("tag count");
      for (long long t = 0; t < tags; ++t) in.integer("element tag value");
      int n = nodes_of(type);
      if (n < 0) in.fail("element type " + std::to_string(type) + " is not supported");
      std::vector<long long> v(n);
      for (auto& x : v) x = in.integer("node tag");
      if (corners_of(type)) b.element(in, tag, v, corners_of(type));
    }
  }
}

}  // namespace

SurfaceMesh read_msh(const std::string& path) {
  detail::TextReader in(path, detail::read_file(path));
  expect(in, "$MeshFormat");
  std::string version = in.token();
  long long file_type = in.integer("file type");
  in.integer("data size");
  if (file_type != 0) in.fail("binary .msh files are not supported: save as ASCII");
  bool v41 = version.rfind("4.1", 0) == 0, v22 = version.rfind("2.2", 0) == 0;
  if (!v41 && !v22)
    in.fail("version " + detail::quoted(version) + " is not supported (4.1 or 2.2)");
  expect(in, "$EndMeshFormat");
  Builder b;
  bool seen_elements = false;
  while (!in.at_end()) {
    std::string section = in.token();
    if (section == "$Nodes" || section == "$Elements") {
      bool nodes = section == "$Nodes";
      if (!nodes) seen_elements = true;
      (v41 ? read_v41 : read_v22)(in, b, nodes);
      expect(in, nodes ? "$EndNodes" : "$EndElements");
    } else if (section.size() > 1 && section[0] == '$') {
      skip_section(in, section);
    } else {
      in.fail("expected a section ($Nodes, $Elements, ...), got " + detail::quoted(section));
    }
  }
  if (!seen_elements || b.mesh.triangles.empty()) {
    throw InputError(path + ": no triangles or quadrangles (a surface needs 2D elements)");
  }
  return std::move(b.mesh);
}

}  // namespace fluidweight
