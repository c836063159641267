#include "solvers/obstacle_contact.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "common/error.hpp"
#include "materials/material.hpp"
#include "solvers/petsc_check.hpp"

namespace hs {
namespace {

// The diagonal of the whole mesh's bounding box (over the ranks).
double bounding_diagonal(const std::vector<double>& X, MPI_Comm comm) {
  double low[3], high[3];
  for (int d = 0; d < 3; ++d) {
    low[d] = std::numeric_limits<double>::max();
    high[d] = -low[d];
  }
  for (size_t k = 0; k < X.size(); ++k) {
    low[k % 3] = std::min(low[k % 3], X[k]);
    high[k % 3] = std::max(high[k % 3], X[k]);
  }
  MPI_Allreduce(MPI_IN_PLACE, low, 3, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, high, 3, MPI_DOUBLE, MPI_MAX, comm);
  return std::hypot(high[0] - low[0], high[1] - low[1], high[2] - low[2]);
}

double triangle_area(const std::vector<double>& X, const int32_t* nodes) {
  const Eigen::Map<const Eigen::Vector3d> a(&X[3 * nodes[0]]), b(&X[3 * nodes[1]]),
      c(&X[3 * nodes[2]]);
  return 0.5 * (b - a).cross(c - a).norm();
}

}  // namespace

ContactBarrier contact_barrier_of(const Config& config, const std::vector<double>& X,
                                  MPI_Comm comm) {
  ContactBarrier barrier;
  barrier.distance =
      config.contact.distance ? *config.contact.distance : 1e-3 * bounding_diagonal(X, comm);
  double E = 0;
  for (const auto& m : config.materials) E = std::max(E, m.law->elastic_constants().E);
  barrier.stiffness =
      config.contact.stiffness ? *config.contact.stiffness : 0.01 * E / barrier.distance;
  return barrier;
}

ObstacleContact::ObstacleContact(const Config& config, const Distribution& dist,
                                 const std::vector<double>& X, Vec work, MPI_Comm comm)
    : comm_(comm),
      obstacles_(config.obstacles),
      project_(config.solver.preset == SolverPreset::gamg),
      X_(X) {
  barrier_ = contact_barrier_of(config, X, comm);

  // Each face of the contact surfaces once (a face in two of the groups too), its area shared
  // equally by its nodes (the lumped area of a P1 face; on P2 faces the corner nodes get a
  // share too, which a quadratic face's consistent integral would not give them).
  const int npf = dist.nodes_per_face();
  std::set<std::array<int32_t, 3>> seen;
  Vec local;
  HS_PETSC(VecSet(work, 0.0));
  HS_PETSC(VecGhostGetLocalForm(work, &local));
  double* a;
  HS_PETSC(VecGetArray(local, &a));
  for (const auto& group : config.contact.surfaces) {
    const auto it = dist.faces.find(group);
    if (it == dist.faces.end()) continue;
    for (size_t f = 0; f < it->second.size() / npf; ++f) {
      const int32_t* nodes = &it->second[f * npf];
      std::array<int32_t, 3> key = {nodes[0], nodes[1], nodes[2]};
      std::sort(key.begin(), key.end());
      if (!seen.insert(key).second) continue;
      const double share = triangle_area(X, nodes) / npf;
      for (int k = 0; k < npf; ++k) a[3 * nodes[k]] += share;
    }
  }
  HS_PETSC(VecRestoreArray(local, &a));
  HS_PETSC(VecGhostRestoreLocalForm(work, &local));
  HS_PETSC(VecGhostUpdateBegin(work, ADD_VALUES, SCATTER_REVERSE));
  HS_PETSC(VecGhostUpdateEnd(work, ADD_VALUES, SCATTER_REVERSE));
  const double* owned;
  HS_PETSC(VecGetArrayRead(work, &owned));
  for (int64_t n = 0; n < dist.num_owned(); ++n)
    if (owned[3 * n] > 0) {
      nodes_.push_back(static_cast<int32_t>(n));
      area_.push_back(owned[3 * n]);
    }
  HS_PETSC(VecRestoreArrayRead(work, &owned));
  int64_t count = static_cast<int64_t>(nodes_.size());
  MPI_Allreduce(&count, &num_nodes_, 1, MPI_INT64_T, MPI_SUM, comm);
  check_start(config.deck_path);
  for (const auto& o : obstacles_) has_friction_ |= o.friction > 0;
  slip_ = config.contact.slip ? *config.contact.slip : 0.1 * barrier_.distance;
  if (has_friction_) {
    const std::vector<double> zero(X.size(), 0.0);
    accept(zero.data(), 0.0);
    begin_step();
  }
}

void ObstacleContact::accept(const double* u, double s) {
  if (!has_friction_) return;
  accepted_.resize(nodes_.size());
  for (size_t i = 0; i < nodes_.size(); ++i) accepted_[i] = position(u, nodes_[i]);
  accepted_s_ = s;
}

void ObstacleContact::begin_step() {
  if (accepted_.empty()) return;
  lag_.resize(nodes_.size());
  for (size_t i = 0; i < nodes_.size(); ++i)
    lag_[i] =
        friction_lag(obstacles_, accepted_[i], accepted_s_, area_[i], barrier_, slip_, lag_[i]);
  accepted_.clear();
}

NodeContact ObstacleContact::evaluate(size_t i, const Eigen::Vector3d& x, double s,
                                      bool project) const {
  if (holds_forces()) return held_load(i, x);
  NodeContact c = node_contact(obstacles_, x, s, area_[i], barrier_, project);
  if (has_friction_ && c.valid) add_friction(obstacles_, lag_[i], x, s, slip_, c);
  return c;
}

// A held force as the node's contact: the load lambda n on the body is the gradient -lambda n
// of the potential -lambda n . x, which has no Hessian; a node past the obstacle's surface is
// the QP's to push back, not a refusal.
NodeContact ObstacleContact::held_load(size_t i, const Eigen::Vector3d& x) const {
  NodeContact c;
  const size_t m = obstacles_.size();
  c.force.assign(m, Eigen::Vector3d::Zero());
  c.stiffness.assign(m, Eigen::Matrix3d::Zero());
  c.active.assign(m, 0);
  const Held& h = held_[i];
  if (h.obstacle < 0 || h.force == 0) return c;
  c.gradient = -h.force * h.normal;
  c.energy = c.gradient.dot(x);
  c.force[h.obstacle] = c.gradient;
  c.active[h.obstacle] = 1;
  return c;
}

void ObstacleContact::hold_forces(const double* u, double s) {
  std::vector<Held> held(nodes_.size());
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const Eigen::Vector3d x = position(u, nodes_[i]);
    const NodeContact c = evaluate(i, x, s, false);
    for (size_t o = 0; o < obstacles_.size(); ++o) {
      const Eigen::Vector3d n = signed_distance(obstacles_[o], x, s).gradient;
      const double f = -c.force[o].dot(n);
      if (f > held[i].force) held[i] = {static_cast<int>(o), n, f};
    }
  }
  held_ = std::move(held);
}

void ObstacleContact::turn_held_normals(const double* u, double s) {
  for (size_t i = 0; i < held_.size(); ++i)
    if (held_[i].force > 0)
      held_[i].normal =
          signed_distance(obstacles_[held_[i].obstacle], position(u, nodes_[i]), s).gradient;
}

std::vector<ObstacleContact::Candidate> ObstacleContact::candidates(const double* u, double s,
                                                                    double reach) const {
  std::vector<Candidate> out;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const Eigen::Vector3d x = position(u, nodes_[i]);
    Candidate best;
    best.gap = std::numeric_limits<double>::max();
    for (size_t o = 0; o < obstacles_.size(); ++o) {
      const SignedDistance sd = signed_distance(obstacles_[o], x, s);
      if (sd.d < best.gap) best = {static_cast<int>(i), static_cast<int>(o), sd.d, sd.gradient};
    }
    if (holds_forces() && held_[i].force > 0) {
      best.obstacle = held_[i].obstacle;
      best.gap = signed_distance(obstacles_[best.obstacle], x, s).d;
      best.normal = held_[i].normal;
    }
    if (best.gap < reach || (holds_forces() && held_[i].force > 0)) out.push_back(best);
  }
  return out;
}

// The undeformed body must start outside every obstacle (in their places at load factor 0):
// the barrier has no energy to start from otherwise.
void ObstacleContact::check_start(const std::string& deck) const {
  struct {
    double d;
    int rank;
  } worst{std::numeric_limits<double>::max(), 0};
  MPI_Comm_rank(comm_, &worst.rank);
  int obstacle = -1;
  Eigen::Vector3d at = Eigen::Vector3d::Zero();
  for (int32_t n : nodes_) {
    const Eigen::Vector3d x(X_[3 * n], X_[3 * n + 1], X_[3 * n + 2]);
    for (size_t o = 0; o < obstacles_.size(); ++o) {
      const double d = signed_distance(obstacles_[o], x, 0.0).d;
      if (d < worst.d) {
        worst.d = d;
        obstacle = static_cast<int>(o);
        at = x;
      }
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm_);
  if (worst.d > 0) return;
  MPI_Bcast(&obstacle, 1, MPI_INT, worst.rank, comm_);
  MPI_Bcast(at.data(), 3, MPI_DOUBLE, worst.rank, comm_);
  char text[200];
  std::snprintf(text, sizeof text,
                "the undeformed body's contact surface reaches %g m into it at (%g, %g, %g): "
                "an obstacle must start outside the body",
                -worst.d, at(0), at(1), at(2));
  throw InputError(deck + ": obstacles[" + std::to_string(obstacle) + "] ('" +
                   obstacles_[obstacle].name + "'): " + text);
}

Eigen::Vector3d ObstacleContact::position(const double* u, int32_t n) const {
  return Eigen::Vector3d(X_[3 * n] + u[3 * n], X_[3 * n + 1] + u[3 * n + 1],
                         X_[3 * n + 2] + u[3 * n + 2]);
}

bool ObstacleContact::add_forces(const double* u, double s, double a, double* r, double* energy) {
  inside_ = -1;
  double sum = 0;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const int32_t n = nodes_[i];
    const NodeContact c = evaluate(i, position(u, n), s, false);
    if (!c.valid && inside_ < 0) inside_ = c.inside;
    sum += c.energy;
    for (int d = 0; d < 3; ++d) r[3 * n + d] += a * c.gradient(d);
  }
  if (energy) *energy = sum;
  return inside_ < 0;
}

bool ObstacleContact::node_terms(const double* u, double s, std::vector<NodeContact>& terms) const {
  terms.resize(nodes_.size());
  for (size_t i = 0; i < nodes_.size(); ++i) {
    terms[i] = evaluate(i, position(u, nodes_[i]), s, false);
    if (!terms[i].valid) return false;
  }
  return true;
}

void ObstacleContact::add_tangent(const double* u, double s, const NodePairBlocks& pairs,
                                  double* values) const {
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const int32_t n = nodes_[i];
    const NodeContact c = evaluate(i, position(u, n), s, project_);
    if (c.hessian.isZero(0)) continue;
    const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> K = c.hessian;
    pairs.add_nodes(&n, 1, K.data(), values);
  }
}

Eigen::Vector3d ObstacleContact::force_on(const double* u, double s, int o,
                                          const std::vector<char>* only) const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const int32_t n = nodes_[i];
    if (only && !(*only)[n]) continue;
    f += evaluate(i, position(u, n), s, false).force[o];
  }
  return f;
}

void ObstacleContact::force_rows(const double* u, double s, int o, const std::vector<char>* only,
                                 double* const rows[3]) const {
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const int32_t n = nodes_[i];
    if (only && !(*only)[n]) continue;
    const NodeContact c = evaluate(i, position(u, n), s, false);
    for (int d = 0; d < 3; ++d)
      for (int j = 0; j < 3; ++j) rows[d][3 * n + j] = c.stiffness[o](d, j);
  }
}

ObstacleContact::Nearest ObstacleContact::nearest(const double* u, double s, int o,
                                                  const std::vector<char>* only) const {
  Nearest best;
  best.gap = std::numeric_limits<double>::max();
  for (int32_t n : nodes_) {
    if (only && !(*only)[n]) continue;
    const SignedDistance sd = signed_distance(obstacles_[o], position(u, n), s);
    if (sd.d < best.gap) {
      best.node = n;
      best.gap = sd.d;
      best.normal = sd.gradient;
    }
  }
  return best;
}

double ObstacleContact::step_limit(const double* u, const double* du, double s) const {
  double alpha = 1;
  if (holds_forces()) return alpha;  // no barrier to keep outside
  for (int32_t n : nodes_) {
    const Eigen::Vector3d x = position(u, n), step(du[3 * n], du[3 * n + 1], du[3 * n + 2]);
    for (const auto& o : obstacles_) alpha = std::min(alpha, step_bound(o, x, step, s));
  }
  return alpha;
}

ObstacleContact::NodeValues ObstacleContact::node_values(const double* u, double s,
                                                         int64_t num_owned) const {
  NodeValues v;
  v.gap.assign(num_owned, 0.0);
  v.pressure.assign(num_owned, 0.0);
  v.friction.assign(3 * num_owned, 0.0);
  for (int64_t n = 0; n < num_owned; ++n) {
    double gap = std::numeric_limits<double>::max();
    for (const auto& o : obstacles_)
      gap = std::min(gap, signed_distance(o, position(u, static_cast<int32_t>(n)), s).d);
    v.gap[n] = gap;
  }
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const int32_t n = nodes_[i];
    const Eigen::Vector3d x = position(u, n);
    const NodeContact normal = holds_forces()
                                   ? held_load(i, x)
                                   : node_contact(obstacles_, x, s, area_[i], barrier_, false);
    for (const auto& f : normal.force) v.pressure[n] += f.norm() / area_[i];
    const Eigen::Vector3d friction = (evaluate(i, x, s, false).gradient - normal.gradient);
    for (int d = 0; d < 3; ++d) v.friction[3 * n + d] = -friction(d) / area_[i];
  }
  return v;
}

ObstacleContact::Totals ObstacleContact::totals(const double* u, double s) const {
  const size_t m = obstacles_.size();
  std::vector<double> sums(4 * m, 0.0);
  double gap = std::numeric_limits<double>::max(), loaded = 0;
  for (size_t i = 0; i < nodes_.size(); ++i) {
    const Eigen::Vector3d x = position(u, nodes_[i]);
    const NodeContact c = evaluate(i, x, s, false);
    if (holds_forces() && held_[i].force > 0)
      loaded = std::max(loaded, std::abs(signed_distance(obstacles_[held_[i].obstacle], x, s).d));
    for (size_t o = 0; o < m; ++o) {
      for (int d = 0; d < 3; ++d) sums[4 * o + d] += c.force[o](d);
      if (c.active[o]) sums[4 * o + 3] += area_[i];
      gap = std::min(gap, signed_distance(obstacles_[o], x, s).d);
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM,
                comm_);
  MPI_Allreduce(MPI_IN_PLACE, &gap, 1, MPI_DOUBLE, MPI_MIN, comm_);
  MPI_Allreduce(MPI_IN_PLACE, &loaded, 1, MPI_DOUBLE, MPI_MAX, comm_);
  Totals t;
  t.loaded_gap = loaded;
  for (size_t o = 0; o < m; ++o) {
    t.force.push_back({sums[4 * o], sums[4 * o + 1], sums[4 * o + 2]});
    t.area.push_back(sums[4 * o + 3]);
  }
  t.min_gap = gap;
  return t;
}

}  // namespace hs
