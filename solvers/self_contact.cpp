#include "solvers/self_contact.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "common/error.hpp"
#include "contact/box_tree.hpp"
#include "contact/pair_friction.hpp"
#include "solvers/gathered_surface.hpp"

namespace hs {
namespace {

Eigen::Vector3d at(const std::vector<double>& x, int32_t i) {
  return Eigen::Vector3d(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
}

Eigen::AlignedBox3d grown(Eigen::AlignedBox3d box, double by) {
  box.min().array() -= by;
  box.max().array() += by;
  return box;
}

// The flat triangles the pairs see on a face of nodes_per_face nodes, as node positions in
// it: a P1 face itself; a P2 face (Tri6: corners 0-2, edge nodes 3 on (0,1), 4 on (1,2), 5 on
// (2,0)) its four sub-triangles, the same way round. The surface is then the P1 surface of all
// its nodes, which keeps every node of it, the edge nodes too, off the others' flat triangles.
const std::vector<std::array<int, 3>>& flat_triangles(int nodes_per_face) {
  static const std::vector<std::array<int, 3>> p1 = {{0, 1, 2}};
  static const std::vector<std::array<int, 3>> p2 = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};
  return nodes_per_face == 6 ? p2 : p1;
}

}  // namespace

SelfContact::SelfContact(const Config& config, const Distribution& dist,
                         const std::vector<char>& constrained, const ContactBarrier& barrier,
                         bool project, MPI_Comm comm)
    : comm_(comm), barrier_(barrier), project_(project) {
  // The surface nodes in the mesh file's numbering, so that their order (and with it every
  // sum over them) does not depend on the number of ranks.
  std::map<int64_t, int64_t> global_of;  // mesh number -> PETSc node number
  std::map<int64_t, std::array<double, 3>> x_of;
  std::map<int64_t, uint64_t> surfaces_of;  // mesh number -> its surfaces' bits
  std::vector<std::array<int64_t, 3>> faces;
  std::vector<int> face_surface;
  const std::vector<std::string>& groups = config.contact.surfaces;
  if (groups.size() > 64)
    throw InputError(config.deck_path + ": contact.surfaces: self-contact takes at most 64");
  for (size_t g = 0; g < groups.size(); ++g) {
    const GatheredSurface s = gather_surface(dist, groups[g], -1, comm);
    for (size_t n = 0; n < s.mesh_nodes.size(); ++n) {
      global_of[s.mesh_nodes[n]] = s.global_nodes[n];
      x_of[s.mesh_nodes[n]] = {s.x[3 * n], s.x[3 * n + 1], s.x[3 * n + 2]};
    }
    for (size_t f = 0; f < s.faces.size() / s.nodes_per_face; ++f)
      for (const auto& flat : flat_triangles(s.nodes_per_face)) {
        std::array<int64_t, 3> face;
        for (int a = 0; a < 3; ++a) {
          face[a] = s.mesh_nodes[s.faces[f * s.nodes_per_face + flat[a]]];
          surfaces_of[face[a]] |= uint64_t{1} << g;
        }
        faces.push_back(face);
        face_surface.push_back(static_cast<int>(g));
      }
  }
  std::map<int64_t, int32_t> index;
  for (const auto& [mesh, global] : global_of) {
    index[mesh] = static_cast<int32_t>(global_.size());
    global_.push_back(global);
    reference_.insert(reference_.end(), x_of[mesh].begin(), x_of[mesh].end());
    node_surfaces_.push_back(surfaces_of[mesh]);
  }
  flat_per_face_ = static_cast<int>(flat_triangles(dist.nodes_per_face()).size());
  const std::vector<double>& x = reference_;
  std::map<std::array<int64_t, 3>, bool> seen;  // a face in two groups counts once
  for (size_t f = 0; f < faces.size(); ++f) {
    std::array<int64_t, 3> key = faces[f];
    std::sort(key.begin(), key.end());
    if (!seen.emplace(key, true).second) continue;
    faces_.push_back({index[faces[f][0]], index[faces[f][1]], index[faces[f][2]]});
    face_surface_.push_back(face_surface[f]);
  }
  const size_t ns = global_.size();
  // A mesh face's area is shared equally by its nodes, as an obstacle's contact nodes share it
  // (its flat triangles are consecutive in faces_).
  area_.assign(ns, 0.0);
  faces_of_.resize(ns);
  for (size_t first = 0; first < faces_.size(); first += flat_per_face_) {
    double area = 0;
    std::set<int32_t> nodes;
    for (size_t f = first; f < first + flat_per_face_; ++f) {
      const auto& t = faces_[f];
      area += 0.5 * (at(x, t[1]) - at(x, t[0])).cross(at(x, t[2]) - at(x, t[0])).norm();
      nodes.insert(t.begin(), t.end());
      for (int32_t n : t) faces_of_[n].push_back(static_cast<int32_t>(f));
    }
    for (int32_t n : nodes) area_[n] += area / static_cast<double>(nodes.size());
  }
  std::map<std::array<int32_t, 2>, int32_t> edge_of;
  for (size_t f = 0; f < faces_.size() && config.contact.edges; ++f) {
    const auto& t = faces_[f];
    const double area = 0.5 * (at(x, t[1]) - at(x, t[0])).cross(at(x, t[2]) - at(x, t[0])).norm();
    for (int k = 0; k < 3; ++k) {
      const std::array<int32_t, 2> e = {std::min(t[k], t[(k + 1) % 3]),
                                        std::max(t[k], t[(k + 1) % 3])};
      const auto [it, added] = edge_of.emplace(e, static_cast<int32_t>(edges_.size()));
      if (added) {
        edges_.push_back(e);
        edge_area_.push_back(0.0);
        edge_length2_.push_back((at(x, e[1]) - at(x, e[0])).squaredNorm());
        edge_surfaces_.push_back(0);
      }
      edge_area_[it->second] += area / 3;
      edge_surfaces_[it->second] |= uint64_t{1} << face_surface_[f];
    }
  }
  const int64_t first = dist.owned_offsets[dist.rank], last = dist.owned_offsets[dist.rank + 1];
  owned_.assign(ns, -1);
  std::vector<int> fixed(3 * ns, 0);
  for (size_t n = 0; n < ns; ++n)
    if (global_[n] >= first && global_[n] < last) {
      owned_[n] = global_[n] - first;
      mine_.push_back(static_cast<int32_t>(n));
      for (int d = 0; d < 3; ++d) fixed[3 * n + d] = constrained[3 * owned_[n] + d];
    }
  MPI_Allreduce(MPI_IN_PLACE, fixed.data(), static_cast<int>(fixed.size()), MPI_INT, MPI_MAX, comm);
  constrained_.assign(fixed.begin(), fixed.end());
  for (size_t e = 0; e < edges_.size(); ++e)
    if (owned_[edges_[e][0]] >= 0) my_edges_.push_back(static_cast<int32_t>(e));
  check_start(config.deck_path);
  const size_t ng = groups.size();
  num_surfaces_ = static_cast<int>(ng);
  friction_.assign(ng * ng, config.contact.friction);
  for (const auto& between : config.contact.friction_between) {
    const auto a = std::find(groups.begin(), groups.end(), between.surfaces[0]) - groups.begin();
    const auto b = std::find(groups.begin(), groups.end(), between.surfaces[1]) - groups.begin();
    friction_[a * ng + b] = friction_[b * ng + a] = between.friction;
  }
  for (double mu : friction_) has_friction_ |= mu > 0;
  slip_ = config.contact.slip ? *config.contact.slip : 0.1 * barrier_.distance;
}

std::vector<double> SelfContact::positions(const double* u) const {
  std::vector<double> x(3 * global_.size(), 0.0);
  for (int32_t n : mine_)
    for (int d = 0; d < 3; ++d) x[3 * n + d] = u[3 * owned_[n] + d];
  MPI_Allreduce(MPI_IN_PLACE, x.data(), static_cast<int>(x.size()), MPI_DOUBLE, MPI_SUM, comm_);
  return x;
}

// Calls visit(feature nodes, count, triangle) for the feature nearest to node p of each triangle
// whose box the tree finds for `box`, skipping the triangles p is a corner of. Every triangle
// counts (a feature shared by two triangles twice): merging the pairs whose nearest feature is the
// same, as the first incremental potential contact does, makes the energy jump where a node
// crosses from a face's region to its edge's, and Newton cycled on the jumps.
template <class Visit>
void each_feature(const std::vector<std::array<int32_t, 3>>& faces, const BoxTree& tree,
                  const std::vector<double>& x, int32_t p, const Eigen::AlignedBox3d& box,
                  Visit&& visit) {
  const Eigen::Vector3d xp = at(x, p);
  tree.overlapping(box, [&](int f) {
    const auto& t = faces[f];
    if (t[0] == p || t[1] == p || t[2] == p) return;
    const TriangleFeature feature = nearest_feature(xp, at(x, t[0]), at(x, t[1]), at(x, t[2]));
    int32_t nodes[4] = {p, -1, -1, -1};
    for (int k = 0; k < feature.count; ++k) nodes[1 + k] = t[feature.vertex[k]];
    visit(nodes, feature.count + 1, static_cast<int32_t>(f));
  });
}

template <class Visit>
bool SelfContact::each_pair(const std::vector<double>& x, bool project, Visit&& visit) const {
  std::vector<Eigen::AlignedBox3d> boxes(faces_.size());  // empty
  for (size_t f = 0; f < faces_.size(); ++f)
    for (int32_t n : faces_[f]) boxes[f].extend(at(x, n));
  const BoxTree tree(std::move(boxes));
  const double dhat = barrier_.distance;
  bool ok = true;
  for (int32_t p : mine_) {
    const Eigen::Vector3d xp = at(x, p);
    each_feature(faces_, tree, x, p, grown(Eigen::AlignedBox3d(xp, xp), dhat),
                 [&](const int32_t* nodes, int count, int32_t face) {
                   Eigen::Vector3d y[4];
                   for (int k = 0; k < count; ++k) y[k] = at(x, nodes[k]);
                   const double d2 = feature_squared_distance(y, count);
                   if (d2 >= dhat * dhat) return;
                   if (!(d2 > 0)) {
                     ok = false;
                     return;
                   }
                   visit(nodes, count, face, pair_barrier(y, count, area_[p], barrier_, project));
                 });
  }
  return ok;
}

template <class Visit>
bool SelfContact::each_edge_pair(const std::vector<double>& x, bool project, Visit&& visit) const {
  std::vector<Eigen::AlignedBox3d> boxes(edges_.size());
  for (size_t e = 0; e < edges_.size(); ++e)
    boxes[e] = Eigen::AlignedBox3d(at(x, edges_[e][0])).extend(at(x, edges_[e][1]));
  const BoxTree tree(boxes);
  const double dhat = barrier_.distance;
  bool ok = true;
  for (int32_t ea : my_edges_)
    tree.overlapping(grown(boxes[ea], dhat), [&](int eb) {
      const auto &a = edges_[ea], &b = edges_[eb];
      if (eb <= ea || a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) return;
      const int32_t nodes[4] = {a[0], a[1], b[0], b[1]};
      Eigen::Vector3d y[4];
      for (int k = 0; k < 4; ++k) y[k] = at(x, nodes[k]);
      const double parallel = 1e-3 * edge_length2_[ea] * edge_length2_[eb];
      if ((y[1] - y[0]).cross(y[3] - y[2]).squaredNorm() <= 0.5 * parallel) return;
      const EdgeFeature feature = nearest_edge_feature(y);
      const double d2 = edge_squared_distance(y, feature);
      if (d2 >= dhat * dhat) return;
      if (!(d2 > 0)) {
        ok = false;
        return;
      }
      const double weight = 0.5 * (edge_area_[ea] + edge_area_[eb]);
      visit(nodes, ea, static_cast<int32_t>(eb),
            edge_pair_barrier(y, feature, weight, parallel, barrier_, project));
    });
  return ok;
}

Eigen::Vector3d SelfContact::Pair::push() const {
  if (!edges) return term.gradient.head<3>();
  return term.gradient.segment<3>(0) + term.gradient.segment<3>(3);
}

std::vector<double> SelfContact::current(const double* u) const {
  std::vector<double> x = positions(u);
  for (size_t k = 0; k < x.size(); ++k) x[k] += reference_[k];
  return x;
}

bool SelfContact::pairs(const double* u, std::vector<Pair>& out) const {
  out.clear();
  const std::vector<double> x = current(u);
  const bool ok =
      each_pair(x, project_, [&](const int32_t* nodes, int count, int32_t, const PairTerm& term) {
        Pair pair;
        pair.count = count;
        std::copy(nodes, nodes + count, pair.node);
        pair.term = term;
        out.push_back(pair);
      });
  const bool edges_ok = each_edge_pair(
      x, project_, [&](const int32_t* nodes, int32_t, int32_t, const PairTerm& term) {
        Pair pair;
        pair.count = 4;
        pair.edges = true;
        std::copy(nodes, nodes + 4, pair.node);
        pair.term = term;
        out.push_back(pair);
      });
  for (const PairFrictionLag& lag : lag_) {
    Pair pair;
    pair.count = lag.count;
    pair.friction = true;
    pair.edges = lag.face < 0;
    Eigen::Vector3d y[4];
    for (int k = 0; k < lag.count; ++k) {
      pair.node[k] = lag.node[k];
      y[k] = at(x, lag.node[k]);
    }
    pair.term = pair_friction(lag, y, slip_);
    out.push_back(pair);
  }
  return ok && edges_ok;
}

double SelfContact::edge_friction(int32_t e, int32_t f) const {
  const size_t ng = static_cast<size_t>(num_surfaces_);
  double mu = 0;
  for (size_t g = 0; g < ng; ++g)
    for (size_t h = 0; h < ng; ++h)
      if ((edge_surfaces_[e] >> g & 1) && (edge_surfaces_[f] >> h & 1))
        mu = std::max(mu, friction_[g * ng + h]);
  return mu;
}

double SelfContact::friction(int32_t p, int32_t f) const {
  const size_t ng = static_cast<size_t>(num_surfaces_);
  double mu = 0;
  for (size_t g = 0; g < ng; ++g)
    if (node_surfaces_[p] >> g & 1) mu = std::max(mu, friction_[g * ng + face_surface_[f]]);
  return mu;
}

void SelfContact::accept(const double* u) {
  if (!has_friction()) return;
  accepted_ = current(u);
}

// Each pair within dhat at the accepted state holds its barrier's force on the node, and a
// pair that held one over the step before (the same node and triangle) carries its slip.
void SelfContact::begin_step() {
  if (accepted_.empty()) return;
  const std::vector<double>& x = accepted_;
  // A node's lag is named by the node and the triangle, an edge pair's (face < 0) by the one
  // edge's nodes and the other edge.
  auto key = [](const PairFrictionLag& l) {
    return std::make_tuple(l.node[0], l.face, l.face < 0 ? l.node[1] : -1);
  };
  auto less = [&](const PairFrictionLag& a, const PairFrictionLag& b) { return key(a) < key(b); };
  // The slip the same pair reached over the step before, zero for a new one.
  auto carried = [&](const PairFrictionLag& probe) {
    const auto before = std::lower_bound(lag_.begin(), lag_.end(), probe, less);
    if (before == lag_.end() || key(*before) != key(probe)) return Eigen::Vector3d::Zero().eval();
    Eigen::Vector3d y[4];
    for (int k = 0; k < before->count; ++k) y[k] = at(x, before->node[k]);
    return pair_slip(*before, y);
  };
  std::vector<PairFrictionLag> lag;
  each_pair(x, project_, [&](const int32_t* nodes, int count, int32_t face, const PairTerm& term) {
    const double mu = friction(nodes[0], face);
    if (mu == 0) return;
    PairFrictionLag probe;
    probe.node[0] = nodes[0];
    probe.face = face;
    Eigen::Vector3d y[4];
    for (int k = 0; k < count; ++k) y[k] = at(x, nodes[k]);
    lag.push_back(pair_friction_lag(nodes, y, count, face, mu, term.gradient.head<3>().norm(),
                                    carried(probe), slip_));
  });
  each_edge_pair(
      x, project_, [&](const int32_t* nodes, int32_t e, int32_t f, const PairTerm& term) {
        const double mu = edge_friction(e, f);
        if (mu == 0) return;
        PairFrictionLag probe;
        probe.node[0] = nodes[0];
        probe.node[1] = nodes[1];
        probe.face = -1 - f;
        Eigen::Vector3d y[4];
        for (int k = 0; k < 4; ++k) y[k] = at(x, nodes[k]);
        const Eigen::Vector3d push = term.gradient.segment<3>(0) + term.gradient.segment<3>(3);
        lag.push_back(edge_friction_lag(nodes, y, nearest_edge_feature(y), probe.face, mu,
                                        push.norm(), carried(probe), slip_));
      });
  std::sort(lag.begin(), lag.end(), less);
  lag_ = std::move(lag);
  accepted_.clear();
}

bool SelfContact::add_forces(const double* u, double a, double* f, double* energy) const {
  std::vector<Pair> found;
  const bool ok = pairs(u, found);
  // The forces per surface node, then the failures and the pairs, in one reduction.
  const size_t n = 3 * global_.size();
  std::vector<double> g(n + 2, 0.0);
  double sum = 0;
  for (const Pair& pair : found) {
    sum += pair.term.energy;
    for (int k = 0; k < pair.count; ++k)
      for (int d = 0; d < 3; ++d) g[3 * pair.node[k] + d] += a * pair.term.gradient(3 * k + d);
  }
  g[n] = ok ? 0 : 1;
  g[n + 1] = static_cast<double>(found.size());
  MPI_Allreduce(MPI_IN_PLACE, g.data(), static_cast<int>(g.size()), MPI_DOUBLE, MPI_SUM, comm_);
  last_pairs_ = static_cast<int64_t>(g[n + 1]);
  for (int32_t p : mine_)
    for (int d = 0; d < 3; ++d) f[3 * owned_[p] + d] += g[3 * p + d];
  if (energy) *energy = sum;
  return g[n] == 0;
}

void SelfContact::add_roundoff(const double* u, double* bound) const {
  std::vector<Pair> found;
  pairs(u, found);
  std::vector<double> x = positions(u), b(3 * global_.size(), 0.0);
  for (size_t k = 0; k < x.size(); ++k) x[k] = std::abs(x[k] + reference_[k]);
  for (const Pair& pair : found)
    for (int i = 0; i < 3 * pair.count; ++i)
      for (int j = 0; j < 3 * pair.count; ++j)
        b[3 * pair.node[i / 3] + i % 3] +=
            std::abs(pair.term.hessian(i, j)) * x[3 * pair.node[j / 3] + j % 3];
  MPI_Allreduce(MPI_IN_PLACE, b.data(), static_cast<int>(b.size()), MPI_DOUBLE, MPI_SUM, comm_);
  for (int32_t n : mine_)
    for (int d = 0; d < 3; ++d) bound[3 * owned_[n] + d] += b[3 * n + d];
}

double SelfContact::step_limit(const double* u, const double* du) const {
  const std::vector<double> x = current(u);
  const std::vector<double> dx = positions(du);
  auto swept = [&](int32_t n) {
    Eigen::AlignedBox3d box(at(x, n));
    return box.extend(at(x, n) + at(dx, n));
  };
  std::vector<Eigen::AlignedBox3d> boxes(faces_.size());  // empty
  for (size_t f = 0; f < faces_.size(); ++f)
    for (int32_t n : faces_[f]) boxes[f].extend(swept(n));
  const BoxTree tree(std::move(boxes));
  // Conservative advancement along the step for each node and triangle whose swept boxes
  // meet: from t, the distance d(t) can fall by at most (t' - t) m by t', so the step may go on
  // to t + (d(t) - d(0) / 10) / m, and again from there.
  auto distance = [&](int32_t p, const std::array<int32_t, 3>& t, double along) {
    Eigen::Vector3d y[4], corner[3];
    const Eigen::Vector3d xp = at(x, p) + along * at(dx, p);
    for (int k = 0; k < 3; ++k) corner[k] = at(x, t[k]) + along * at(dx, t[k]);
    const TriangleFeature feature = nearest_feature(xp, corner[0], corner[1], corner[2]);
    y[0] = xp;
    for (int k = 0; k < feature.count; ++k) y[1 + k] = corner[feature.vertex[k]];
    return std::sqrt(feature_squared_distance(y, feature.count + 1));
  };
  double alpha = 1;
  auto advance = [&](double relative, auto&& distance_at) {
    const double d0 = distance_at(0.0);
    if (relative <= 0.9 * d0) return;
    double along = 0;
    for (int k = 0; k < 100 && along < alpha; ++k) {
      const double d = k == 0 ? d0 : distance_at(along);
      if (d <= 0.1 * d0 * (1 + 1e-12)) break;
      along = std::min(1.0, along + (d - 0.1 * d0) / relative);
      if (along == 1.0) return;
    }
    alpha = std::min(alpha, along);
  };
  for (int32_t p : mine_)
    tree.overlapping(grown(swept(p), barrier_.distance), [&](int f) {
      const auto& t = faces_[f];
      if (t[0] == p || t[1] == p || t[2] == p) return;
      double relative = 0;
      for (int32_t n : t) relative = std::max(relative, (at(dx, n) - at(dx, p)).norm());
      advance(relative, [&](double along) { return distance(p, t, along); });
    });
  // The same for the pairs of edges: a point of one edge moves by at most the largest
  // |du_i - du_j| (i of the one edge, j of the other) relative to a point of the other.
  std::vector<Eigen::AlignedBox3d> edge_boxes(edges_.size());
  for (size_t e = 0; e < edges_.size(); ++e)
    edge_boxes[e] = swept(edges_[e][0]).extend(swept(edges_[e][1]));
  const BoxTree edge_tree(edge_boxes);
  for (int32_t ea : my_edges_)
    edge_tree.overlapping(grown(edge_boxes[ea], barrier_.distance), [&](int eb) {
      const auto &a = edges_[ea], &b = edges_[eb];
      if (eb <= ea || a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) return;
      const int32_t nodes[4] = {a[0], a[1], b[0], b[1]};
      double relative = 0;
      for (int i = 0; i < 2; ++i)
        for (int j = 2; j < 4; ++j)
          relative = std::max(relative, (at(dx, nodes[i]) - at(dx, nodes[j])).norm());
      advance(relative, [&](double along) {
        Eigen::Vector3d y[4];
        for (int k = 0; k < 4; ++k) y[k] = at(x, nodes[k]) + along * at(dx, nodes[k]);
        return std::sqrt(edge_squared_distance(y, nearest_edge_feature(y)));
      });
    });
  MPI_Allreduce(MPI_IN_PLACE, &alpha, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return alpha;
}

void SelfContact::pattern_dofs(size_t k, int64_t rows[3], int64_t cols[3]) const {
  for (int d = 0; d < 3; ++d) {
    const int32_t a = pattern_[k][0], b = pattern_[k][1];
    rows[d] = constrained_[3 * a + d] ? -1 : 3 * global_[a] + d;
    cols[d] = constrained_[3 * b + d] ? -1 : 3 * global_[b] + d;
  }
}

bool SelfContact::extend_pattern(const std::vector<Pair>& found) {
  std::vector<std::array<int32_t, 2>> missing;
  for (const Pair& pair : found)
    for (int i = 0; i < pair.count; ++i)
      for (int j = 0; j < pair.count; ++j) {
        const std::array<int32_t, 2> key = {pair.node[i], pair.node[j]};
        if (!std::binary_search(pattern_.begin(), pattern_.end(), key)) missing.push_back(key);
      }
  int grew = !missing.empty();
  MPI_Allreduce(MPI_IN_PLACE, &grew, 1, MPI_INT, MPI_MAX, comm_);
  pattern_.insert(pattern_.end(), missing.begin(), missing.end());
  std::sort(pattern_.begin(), pattern_.end());
  pattern_.erase(std::unique(pattern_.begin(), pattern_.end()), pattern_.end());
  return grew != 0;
}

void SelfContact::fill_tangent(const std::vector<Pair>& found, double* values) const {
  std::fill(values, values + 9 * pattern_.size(), 0.0);
  for (const Pair& pair : found)
    for (int i = 0; i < pair.count; ++i)
      for (int j = 0; j < pair.count; ++j) {
        const std::array<int32_t, 2> key = {pair.node[i], pair.node[j]};
        const auto slot =
            std::lower_bound(pattern_.begin(), pattern_.end(), key) - pattern_.begin();
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            values[9 * slot + 3 * r + c] += pair.term.hessian(3 * i + r, 3 * j + c);
      }
}

int SelfContact::side(int32_t p, int32_t f, int a, int b) const {
  return int((node_surfaces_[p] >> a & 1) && face_surface_[f] == b) -
         int((node_surfaces_[p] >> b & 1) && face_surface_[f] == a);
}

int SelfContact::edge_side(int32_t e, int32_t f, int a, int b) const {
  auto in = [&](int32_t edge, int s) { return (edge_surfaces_[edge] >> s & 1) != 0; };
  return int(in(e, a) && in(f, b)) - int(in(e, b) && in(f, a));
}

std::array<double, 3> SelfContact::force_between(const double* u, int a, int b) const {
  std::array<double, 3> force = {0, 0, 0};
  const std::vector<double> x = current(u);
  each_pair(x, false, [&](const int32_t* nodes, int, int32_t face, const PairTerm& term) {
    const int s = side(nodes[0], face, a, b);
    for (int d = 0; d < 3; ++d) force[d] += s * term.gradient(d);
  });
  each_edge_pair(x, false, [&](const int32_t*, int32_t e, int32_t f, const PairTerm& term) {
    const int s = edge_side(e, f, a, b);
    for (int d = 0; d < 3; ++d) force[d] += s * (term.gradient(d) + term.gradient(3 + d));
  });
  MPI_Allreduce(MPI_IN_PLACE, force.data(), 3, MPI_DOUBLE, MPI_SUM, comm_);
  return force;
}

double SelfContact::force_rows_between(const double* u, int a, int b, double* rows[3]) const {
  const std::vector<double> x = current(u);
  const size_t ns = global_.size();
  // Per surface node the 3 x 3 block dF_d/dx_node, then whether any pair acts.
  std::vector<double> r(9 * ns + 1, 0.0);
  each_pair(x, false, [&](const int32_t* nodes, int count, int32_t face, const PairTerm& term) {
    const int s = side(nodes[0], face, a, b);
    if (s == 0) return;
    r[9 * ns] = 1;
    for (int k = 0; k < count; ++k)
      for (int d = 0; d < 3; ++d)
        for (int c = 0; c < 3; ++c) r[9 * nodes[k] + 3 * d + c] += s * term.hessian(d, 3 * k + c);
  });
  each_edge_pair(x, false, [&](const int32_t* nodes, int32_t e, int32_t f, const PairTerm& term) {
    const int s = edge_side(e, f, a, b);
    if (s == 0) return;
    r[9 * ns] = 1;
    for (int k = 0; k < 4; ++k)
      for (int d = 0; d < 3; ++d)
        for (int c = 0; c < 3; ++c)
          r[9 * nodes[k] + 3 * d + c] +=
              s * (term.hessian(d, 3 * k + c) + term.hessian(3 + d, 3 * k + c));
  });
  MPI_Allreduce(MPI_IN_PLACE, r.data(), static_cast<int>(r.size()), MPI_DOUBLE, MPI_SUM, comm_);
  for (int32_t p : mine_)
    for (int d = 0; d < 3; ++d)
      for (int c = 0; c < 3; ++c) rows[d][3 * owned_[p] + c] = r[9 * p + 3 * d + c];
  if (r[9 * ns] > 0) return 0;
  // No pair acts: the nearest node of either surface to a face of the other, and the weights
  // of its nearest point there, q = sum beta_k x_k.
  struct Near {
    double d2 = std::numeric_limits<double>::infinity();
    double sign = 0, beta[3] = {0, 0, 0}, n[3] = {0, 0, 0};
    int32_t node[4] = {-1, -1, -1, -1};
  } near;
  for (const int from : {a, b}) {
    const int to = from == a ? b : a;
    std::vector<int32_t> faces;
    std::vector<Eigen::AlignedBox3d> boxes;
    for (size_t f = 0; f < faces_.size(); ++f)
      if (face_surface_[f] == to) {
        faces.push_back(static_cast<int32_t>(f));
        boxes.emplace_back();
        for (int32_t n : faces_[f]) boxes.back().extend(at(x, n));
      }
    const BoxTree tree(std::move(boxes));
    for (int32_t p : mine_) {
      if (!(node_surfaces_[p] >> from & 1)) continue;
      const Eigen::Vector3d xp = at(x, p);
      tree.nearest(xp, near.d2, [&](int i) {
        const auto& t = faces_[faces[i]];
        if (t[0] == p || t[1] == p || t[2] == p) return;
        const TriangleFeature feature = nearest_feature(xp, at(x, t[0]), at(x, t[1]), at(x, t[2]));
        Eigen::Vector3d y[4] = {xp};
        for (int k = 0; k < feature.count; ++k) y[1 + k] = at(x, t[feature.vertex[k]]);
        const double d2 = feature_squared_distance(y, feature.count + 1);
        if (!(d2 < near.d2) || !(d2 > 0)) return;
        near = Near();
        near.d2 = d2;
        near.sign = from == a ? 1 : -1;
        near.node[0] = p;
        feature_weights(y, feature.count + 1, near.beta);
        Eigen::Vector3d q = Eigen::Vector3d::Zero();
        for (int k = 0; k < feature.count; ++k) {
          near.node[1 + k] = t[feature.vertex[k]];
          q += near.beta[k] * y[1 + k];
        }
        Eigen::Map<Eigen::Vector3d>(near.n) = (xp - q).normalized();
      });
    }
  }
  struct {
    double d;
    int rank;
  } best{std::sqrt(near.d2), 0};
  MPI_Comm_rank(comm_, &best.rank);
  MPI_Allreduce(MPI_IN_PLACE, &best, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm_);
  if (!std::isfinite(best.d)) return best.d;
  MPI_Bcast(&near, sizeof near, MPI_BYTE, best.rank, comm_);
  // The spring on the gap's closing: the node's move less its nearest point's.
  for (int k = 0; k < 4 && near.node[k] >= 0; ++k) {
    if (owned_[near.node[k]] < 0) continue;
    const double w = k == 0 ? near.sign : -near.sign * near.beta[k - 1];
    for (int d = 0; d < 3; ++d)
      for (int c = 0; c < 3; ++c)
        rows[d][3 * owned_[near.node[k]] + c] += w * near.n[d] * near.n[c];
  }
  return best.d;
}

SelfContact::Totals SelfContact::totals(const double* u) const {
  std::vector<Pair> found;
  pairs(u, found);
  Totals t;
  t.min_gap = std::numeric_limits<double>::infinity();
  for (const Pair& pair : found) {
    if (pair.friction) {
      t.friction += pair.push().norm();
      continue;
    }
    ++t.pairs;
    t.force += pair.push().norm();
    t.min_gap = std::min(t.min_gap, pair.term.distance);
  }
  MPI_Allreduce(MPI_IN_PLACE, &t.pairs, 1, MPI_INT64_T, MPI_SUM, comm_);
  double sums[2] = {t.force, t.friction};
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, comm_);
  t.force = sums[0];
  t.friction = sums[1];
  MPI_Allreduce(MPI_IN_PLACE, &t.min_gap, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return t;
}

SelfContact::NodeValues SelfContact::node_values(const double* u, int64_t num_owned) const {
  std::vector<Pair> found;
  pairs(u, found);
  const double dhat = barrier_.distance;
  const size_t ns = global_.size();
  std::vector<double> g(6 * ns, 0.0), gap(ns, dhat);  // the barriers' forces, then friction's
  for (const Pair& pair : found)
    for (int k = 0; k < pair.count; ++k) {
      const int32_t n = pair.node[k];
      const size_t at_n = 3 * n + (pair.friction ? 3 * ns : 0);
      for (int d = 0; d < 3; ++d) g[at_n + d] += pair.term.gradient(3 * k + d);
      if (!pair.friction) gap[n] = std::min(gap[n], pair.term.distance);
    }
  MPI_Allreduce(MPI_IN_PLACE, g.data(), static_cast<int>(g.size()), MPI_DOUBLE, MPI_SUM, comm_);
  MPI_Allreduce(MPI_IN_PLACE, gap.data(), static_cast<int>(gap.size()), MPI_DOUBLE, MPI_MIN, comm_);
  NodeValues v;
  v.gap.assign(num_owned, dhat);
  v.pressure.assign(num_owned, 0.0);
  if (has_friction()) v.friction.assign(3 * num_owned, 0.0);
  for (int32_t n : mine_) {
    v.gap[owned_[n]] = gap[n];
    v.pressure[owned_[n]] = at(g, n).norm() / area_[n];
    // The traction on the body: the pairs' friction force on the node, less its dE/du.
    for (int d = 0; d < 3 && has_friction(); ++d)
      v.friction[3 * owned_[n] + d] = -g[3 * ns + 3 * n + d] / area_[n];
  }
  return v;
}

void SelfContact::check_start(const std::string& deck) const {
  const std::vector<double>& x = reference_;
  std::vector<Eigen::AlignedBox3d> boxes(faces_.size());  // empty
  for (size_t f = 0; f < faces_.size(); ++f)
    for (int32_t n : faces_[f]) boxes[f].extend(at(x, n));
  const BoxTree tree(std::move(boxes));
  struct {
    double d;
    int rank;
  } worst{std::numeric_limits<double>::infinity(), 0};
  MPI_Comm_rank(comm_, &worst.rank);
  Eigen::Vector3d where = Eigen::Vector3d::Zero();
  for (int32_t p : mine_) {
    const Eigen::Vector3d xp = at(x, p);
    each_feature(faces_, tree, x, p, grown(Eigen::AlignedBox3d(xp, xp), barrier_.distance),
                 [&](const int32_t* nodes, int count, int32_t) {
                   Eigen::Vector3d y[4];
                   for (int k = 0; k < count; ++k) y[k] = at(x, nodes[k]);
                   const double d = std::sqrt(feature_squared_distance(y, count));
                   if (d < worst.d) {
                     worst.d = d;
                     where = xp;
                   }
                 });
  }
  const bool apart =
      each_edge_pair(x, false, [&](const int32_t* nodes, int32_t, int32_t, const PairTerm& term) {
        if (term.distance >= worst.d) return;
        worst.d = term.distance;
        where = 0.5 * (at(x, nodes[0]) + at(x, nodes[1]));
      });
  if (!apart) worst.d = 0;
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm_);
  if (worst.d >= barrier_.distance) return;
  MPI_Bcast(where.data(), 3, MPI_DOUBLE, worst.rank, comm_);
  char text[300];
  std::snprintf(text, sizeof text,
                "the undeformed surface's node or edge at (%g, %g, %g) lies %g m from a triangle "
                "or an edge of the contact surfaces it does not touch, within the barrier's "
                "distance %g m: make contact.distance smaller than the surfaces' gaps",
                where(0), where(1), where(2), worst.d, barrier_.distance);
  throw InputError(deck + ": contact.self: " + text);
}

}  // namespace hs
