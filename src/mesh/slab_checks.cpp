// check_mesh_slab in four collective steps, each ended by throw_together: the tetrahedra with
// their nodes' coordinates (asked from the nodes' blocks, as distribute_slabs asks them), the
// nodes in space, the faces of the tetrahedra, the surface faces.
#include "mesh/slab_checks.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/exchange.hpp"
#include "mesh/mesh_checks.hpp"
#include "mesh/mesh_distribute.hpp"
#include "mesh/tet_numbering.hpp"

namespace hs {
namespace {

using tet::kEdgeNode;
using tet::kOutwardFace;
using tet::node_x;
using tet::odd_order;

// The tolerance of check_duplicate_nodes, as a fraction of the mesh's extent.
constexpr double kSamePlace = 1e-12;

// all_to_all, the lists sent given up: on one process (load_mesh reads an .h5 whole) without
// the two copies that all_to_all makes, which cost more here than the checks themselves.
template <class T>
std::vector<T> exchange(std::vector<std::vector<T>>& send, MPI_Comm comm,
                        std::vector<int64_t>* from = nullptr) {
  if (send.size() == 1) {
    if (from) *from = {static_cast<int64_t>(send[0].size())};
    std::vector<T> mine = std::move(send[0]);
    send = {};
    return mine;
  }
  std::vector<T> received = all_to_all(send, comm, from);
  send = {};
  return received;
}

struct Point {
  double x[3];
};

std::string point_text(const double* x) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << x[0] << ", " << x[1] << ", " << x[2] << ")";
  return s.str();
}

// ---- 1. Tetrahedra: every node used, orientation, P2 Jacobians ---------------------------

// The slab's tetrahedra as a Mesh of their own, numbered locally, with their nodes'
// coordinates; its labels name them and their nodes by their rows in the file.
struct LocalTets {
  Mesh mesh;
  MeshLabels labels;
};

LocalTets local_tets(const MeshSlab& slab, const std::string& file, MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  // The tetrahedra's nodes sorted with where they occur: the distinct nodes and the local
  // numbering in one pass.
  std::vector<std::pair<int64_t, int64_t>> occurrences(slab.tets.size());
  for (size_t i = 0; i < slab.tets.size(); ++i) occurrences[i] = {slab.tets[i], i};
  std::sort(occurrences.begin(), occurrences.end());
  LocalTets t;
  t.mesh.order = slab.order;
  t.mesh.tets.resize(slab.tets.size());
  std::vector<int64_t> nodes;
  for (const auto& [node, at] : occurrences) {
    if (nodes.empty() || nodes.back() != node) nodes.push_back(node);
    t.mesh.tets[at] = static_cast<int64_t>(nodes.size()) - 1;
  }
  occurrences = {};
  std::vector<std::vector<int64_t>> ask(size);
  for (int64_t n : nodes) ask[block_owner(slab.num_nodes, n, size)].push_back(n);
  std::vector<int64_t> asked_by;
  std::vector<int64_t> asked = exchange(ask, comm, &asked_by);
  std::vector<char> used(slab.slab_nodes(), 0);
  std::vector<std::vector<Point>> reply(size);
  size_t k = 0;
  for (int r = 0; r < size; ++r) {
    reply[r].reserve(asked_by[r]);
    for (int64_t i = 0; i < asked_by[r]; ++i, ++k) {
      const int64_t b = asked[k] - slab.node_begin;
      used[b] = 1;
      reply[r].push_back({{slab.x[3 * b], slab.x[3 * b + 1], slab.x[3 * b + 2]}});
    }
  }
  asked = {};
  std::string error;
  for (int64_t b = 0; b < slab.slab_nodes() && error.empty(); ++b)
    if (!used[b])
      error = file + ": node " + std::to_string(slab.node_begin + b) + " at " +
              point_text(&slab.x[3 * b]) + " belongs to no element";
  throw_together<InputError>(error, comm);
  // In the order of `nodes`: each rank's block follows the lower ranks'.
  const std::vector<Point> x = exchange(reply, comm);
  t.mesh.x.reserve(3 * x.size());
  for (const Point& p : x) t.mesh.x.insert(t.mesh.x.end(), p.x, p.x + 3);
  t.labels.node_tags.assign(nodes.begin(), nodes.end());
  t.labels.tet_tags.resize(slab.slab_tets());
  for (int64_t i = 0; i < slab.slab_tets(); ++i) t.labels.tet_tags[i] = slab.tet_begin + i;
  return t;
}

// The first degenerate or inverted tetrahedron, as orient_tets_positively measures them; an
// inverted one is not renumbered here: the writer wrote every one positive.
std::string orientation_error(const LocalTets& t, const std::string& file) {
  const Mesh& m = t.mesh;
  const int npe = m.nodes_per_tet();
  for (int64_t e = 0; e < m.num_tets(); ++e) {
    const int64_t* v = &m.tets[npe * e];
    Eigen::Matrix3d edges;
    for (int i = 0; i < 3; ++i) edges.col(i) = node_x(m, v[i + 1]) - node_x(m, v[0]);
    const double det = edges.determinant();
    const double scale = edges.colwise().norm().maxCoeff();
    if (!(std::abs(det) > 1e-12 * scale * scale * scale))
      return file + ": " + t.labels.tet(m, e) + " is degenerate (zero volume)";
    if (det < 0)
      return file + ": " + t.labels.tet(m, e) +
             " is inverted: its vertices are in negative order, which hydrosoft never writes "
             "(the file was altered)";
  }
  return {};
}

void check_tets(const MeshSlab& slab, const std::string& file, MPI_Comm comm) {
  const LocalTets t = local_tets(slab, file, comm);
  throw_together<InputError>(orientation_error(t, file), comm);
  std::string error;
  try {
    check_curved_tets(t.mesh, file, t.labels);
  } catch (const InputError& e) {
    error = e.what();
  }
  throw_together<InputError>(error, comm);
}

// ---- 2. Nodes at the same place -------------------------------------------------------------

// A node, sent to the rank of its cell (home) or of a neighbouring cell whose border it lies
// within the tolerance of (guest).
struct NodeAt {
  double x[3];
  int64_t node;
  int32_t guest;
};

// Nodes within kSamePlace of the extent of each other, found by cells in space: each node goes
// to the rank its cell hashes to, and to the rank of a neighbouring cell too when it lies
// within the tolerance of that cell (a few in a million, with cells of 2^-20 of the extent).
// There, nodes are sorted by a grid of the tolerance's size, and each home node is compared
// with those of the 27 grid cells around it, walked with 9 cursors that only move forward.
// Nodes that pass lie more than the tolerance apart, so only a bounded number of them fit in
// those cells: the work is linear after the sort, whatever the file holds.
void check_same_place(const MeshSlab& slab, const std::string& file, MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  if (slab.num_nodes < 2) return;
  double lo[3], hi[3];
  std::fill_n(lo, 3, std::numeric_limits<double>::infinity());
  std::fill_n(hi, 3, -std::numeric_limits<double>::infinity());
  for (int64_t i = 0; i < slab.slab_nodes(); ++i)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], slab.x[3 * i + d]);
      hi[d] = std::max(hi[d], slab.x[3 * i + d]);
    }
  MPI_Allreduce(MPI_IN_PLACE, lo, 3, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, hi, 3, MPI_DOUBLE, MPI_MAX, comm);
  // Halves: the extent of finite coordinates may overflow a double (1e308 - -1e308).
  double half = 0;
  for (int d = 0; d < 3; ++d) half = std::max(half, hi[d] / 2 - lo[d] / 2);
  if (!(half > 0)) half = 1;  // every node at one place
  // Coordinates as fractions of the extent, 0 to 1.
  auto unit = [&](const double* x, int d) { return (x[d] / 2 - lo[d] / 2) / half; };
  constexpr double kCell = 1.0 / (1 << 20);
  using Key = std::array<int64_t, 3>;
  auto cell_rank = [&](const Key& c) {
    return static_cast<int>(spread(spread(spread(c[0]) ^ c[1]) ^ c[2]) % size);
  };

  std::vector<std::vector<NodeAt>> out(size);
  for (int64_t i = 0; i < slab.slab_nodes(); ++i) {
    const double* x = &slab.x[3 * i];
    Key home;
    int low[3], high[3];  // the neighbouring cells it lies near, per direction: -1, 0, +1
    for (int d = 0; d < 3; ++d) {
      const double u = unit(x, d);
      home[d] = static_cast<int64_t>(std::floor(u / kCell));
      low[d] = u - home[d] * kCell < 2 * kSamePlace ? -1 : 0;
      high[d] = (home[d] + 1) * kCell - u < 2 * kSamePlace ? 1 : 0;
    }
    const int r0 = cell_rank(home);
    const NodeAt record{{x[0], x[1], x[2]}, slab.node_begin + i, 0};
    out[r0].push_back(record);
    int sent[27], nsent = 0;  // ranks that already have it
    sent[nsent++] = r0;
    for (int a = low[0]; a <= high[0]; ++a)
      for (int b = low[1]; b <= high[1]; ++b)
        for (int c = low[2]; c <= high[2]; ++c) {
          const int r = cell_rank({home[0] + a, home[1] + b, home[2] + c});
          if (std::find(sent, sent + nsent, r) != sent + nsent) continue;
          sent[nsent++] = r;
          out[r].push_back(record);
          out[r].back().guest = 1;
        }
  }
  std::vector<NodeAt> mine = exchange(out, comm);

  std::vector<std::pair<Key, int64_t>> order(mine.size());  // grid key, index in mine
  for (size_t i = 0; i < mine.size(); ++i) {
    for (int d = 0; d < 3; ++d)
      order[i].first[d] = static_cast<int64_t>(std::floor(unit(mine[i].x, d) / kSamePlace));
    order[i].second = static_cast<int64_t>(i);
  }
  std::sort(order.begin(), order.end());
  auto close = [&](const NodeAt& a, const NodeAt& b) {
    double d2 = 0;
    for (int d = 0; d < 3; ++d) d2 += std::pow(unit(a.x, d) - unit(b.x, d), 2);
    return d2 <= kSamePlace * kSamePlace;
  };
  std::string error;
  size_t cursor[3][3] = {};
  for (size_t i = 0; i < order.size() && error.empty(); ++i) {
    const NodeAt& a = mine[order[i].second];
    if (a.guest) continue;
    const Key& key = order[i].first;
    for (int dx = -1; dx <= 1 && error.empty(); ++dx)
      for (int dy = -1; dy <= 1 && error.empty(); ++dy) {
        const Key first{key[0] + dx, key[1] + dy, key[2] - 1},
            last{key[0] + dx, key[1] + dy, key[2] + 1};
        size_t& j = cursor[dx + 1][dy + 1];
        while (j < order.size() && order[j].first < first) ++j;
        for (size_t k = j; k < order.size() && !(last < order[k].first); ++k) {
          const NodeAt& b = mine[order[k].second];
          if (b.node == a.node || !close(a, b)) continue;
          const NodeAt& p = a.node < b.node ? a : b;
          const NodeAt& q = a.node < b.node ? b : a;
          error = file + ": node " + std::to_string(p.node) + " at " + point_text(p.x) +
                  " and node " + std::to_string(q.node) + " at " + point_text(q.x) +
                  " are at the same place: the elements on either side are not connected (a "
                  "crack, or a volume meshed twice)";
          break;
        }
      }
  }
  throw_together<InputError>(error, comm);
}

// ---- 3. Faces shared on the same side -------------------------------------------------------

struct FaceSide {
  std::array<int64_t, 3> v;  // sorted vertices
  // 2 x the tetrahedron, + 1 when its outward order of the vertices is an odd permutation of
  // v (one word: the faces are the largest records of the checks)
  int64_t side;
  int64_t tet() const { return side >> 1; }
  bool odd() const { return side & 1; }
};

// Every face goes to the rank its vertices hash to. Two positively oriented tetrahedra that
// share a face see it in opposite outward orders; among three or more, two see it alike, so
// the first three of a face decide.
void check_faces(const MeshSlab& slab, const std::string& file, MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const int npe = slab.nodes_per_tet();
  std::vector<std::vector<FaceSide>> out(size);
  for (auto& list : out) list.reserve(4 * slab.slab_tets() / size * 11 / 10);  // hashing spreads
  for (int64_t i = 0; i < slab.slab_tets(); ++i)
    for (const auto& f : kOutwardFace) {
      const int64_t* t = &slab.tets[npe * i];
      FaceSide s{{t[f[0]], t[f[1]], t[f[2]]}, 2 * (slab.tet_begin + i)};
      s.side += odd_order(s.v[0], s.v[1], s.v[2]);
      std::sort(s.v.begin(), s.v.end());
      out[face_rank(s.v, size)].push_back(s);
    }
  std::vector<FaceSide> mine = exchange(out, comm);
  std::sort(mine.begin(), mine.end(), [](const FaceSide& a, const FaceSide& b) {
    if (a.v[0] != b.v[0]) return a.v[0] < b.v[0];
    if (a.v[1] != b.v[1]) return a.v[1] < b.v[1];
    if (a.v[2] != b.v[2]) return a.v[2] < b.v[2];
    return a.side < b.side;
  });
  auto same_face = [](const FaceSide& a, const FaceSide& b) {
    return a.v[0] == b.v[0] && a.v[1] == b.v[1] && a.v[2] == b.v[2];
  };
  std::string error;
  for (size_t i = 0; i < mine.size() && error.empty();) {
    size_t end = i + 1;
    while (end < mine.size() && same_face(mine[end], mine[i])) ++end;
    for (size_t a = i; a < std::min(end, i + 3) && error.empty(); ++a)
      for (size_t b = a + 1; b < std::min(end, i + 3); ++b)
        if (mine[a].odd() == mine[b].odd()) {
          error = file + ": elements " + std::to_string(mine[a].tet()) + " and " +
                  std::to_string(mine[b].tet()) +
                  " (rows of /tets) overlap: they share a face and lie on the same side of it "
                  "(an element listed twice, or folded over its neighbour)";
          break;
        }
    i = end;
  }
  throw_together<InputError>(error, comm);
}

// ---- 4. Surface faces against their tetrahedra ----------------------------------------------

struct SurfaceFace {
  int64_t nodes[6];
  int64_t tet, row;
  int32_t group;  // index among the slab's surface groups (a std::map: the same on every rank)
};

std::string node_list(const int64_t* nodes, int n) {
  std::string s;
  for (int k = 0; k < n; ++k) s += (k ? " " : "") + std::to_string(nodes[k]);
  return s;
}

// Empty, or why face f is not the face of its tetrahedron `tet` (npe nodes) listed outwards.
std::string surface_face_error(const SurfaceFace& f, const int64_t* tet, int order) {
  const int npf = order == 1 ? 3 : 6;
  const std::string bounds = "element " + std::to_string(f.tet);
  for (const auto& face : kOutwardFace) {
    // Where the face's first vertex is in the tetrahedron's outward order of this face.
    int at = -1;
    for (int k = 0; k < 3; ++k)
      if (tet[face[k]] == f.nodes[0]) at = k;
    if (at < 0) continue;
    const int next = face[(at + 1) % 3], last = face[(at + 2) % 3];
    const bool outward = tet[next] == f.nodes[1] && tet[last] == f.nodes[2];
    const bool inward = tet[last] == f.nodes[1] && tet[next] == f.nodes[2];
    if (inward)
      return "is listed inwards: its normal points into " + bounds +
             ", which it bounds (a pressure on it would push the wrong way); hydrosoft writes "
             "every surface face outwards, so the file was altered";
    if (!outward) continue;
    if (order == 1) return {};
    const int v[3] = {face[at], next, last};
    int64_t edges[3];  // a P2 tetrahedron's edge nodes follow its 4 vertices
    for (int k = 0; k < 3; ++k) edges[k] = tet[kEdgeNode[v[k]][v[(k + 1) % 3]]];
    if (!std::equal(edges, edges + 3, f.nodes + 3))
      return "has edge nodes " + node_list(f.nodes + 3, 3) + " where the face of " + bounds +
             " has " + node_list(edges, 3);
    return {};
  }
  return "(nodes " + node_list(f.nodes, npf) + ") is not a face of " + bounds +
         ", which its group's tets says it bounds";
}

// Every surface face goes to the rank that holds the block of the tetrahedron it names.
void check_surfaces(const MeshSlab& slab, const std::string& file, MPI_Comm comm) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  const int npe = slab.nodes_per_tet(), npf = slab.nodes_per_face();
  std::vector<std::string> names;
  std::vector<std::vector<SurfaceFace>> out(size);
  for (const auto& [name, faces] : slab.surfaces) {
    for (size_t f = 0; f < faces.tets.size(); ++f) {
      SurfaceFace s{{},
                    faces.tets[f],
                    faces.begin + static_cast<int64_t>(f),
                    static_cast<int32_t>(names.size())};
      std::copy_n(&faces.nodes[npf * f], npf, s.nodes);
      out[block_owner(slab.num_tets, s.tet, size)].push_back(s);
    }
    names.push_back(name);
  }
  std::vector<SurfaceFace> mine = exchange(out, comm);
  std::sort(mine.begin(), mine.end(), [](const SurfaceFace& a, const SurfaceFace& b) {
    return a.group != b.group ? a.group < b.group : a.row < b.row;
  });
  std::string error;
  for (const SurfaceFace& f : mine) {
    const std::string why =
        surface_face_error(f, &slab.tets[npe * (f.tet - slab.tet_begin)], slab.order);
    if (why.empty()) continue;
    error =
        file + ": /surfaces/" + names[f.group] + "/faces: row " + std::to_string(f.row) + " " + why;
    break;
  }
  throw_together<InputError>(error, comm);
}

}  // namespace

void check_mesh_slab(const MeshSlab& slab, MPI_Comm comm) {
  const std::string file = slab.file.empty() ? "mesh" : slab.file;
  check_tets(slab, file, comm);
  check_same_place(slab, file, comm);
  check_faces(slab, file, comm);
  check_surfaces(slab, file, comm);
}

}  // namespace hs
