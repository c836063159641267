#include "solvers/effectors.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "fem/shape.hpp"

namespace hs {

namespace {

// Shares the point `from` found with every rank.
void share(MaterialPoint& p, int from, MPI_Comm comm) {
  int n = static_cast<int>(p.nodes.size());
  MPI_Bcast(&n, 1, MPI_INT, from, comm);
  p.nodes.resize(n);
  p.N.resize(n);
  p.free_dofs.resize(3 * n);
  MPI_Bcast(p.nodes.data(), n, MPI_INT64_T, from, comm);
  MPI_Bcast(p.N.data(), n, MPI_DOUBLE, from, comm);
  MPI_Bcast(p.free_dofs.data(), 3 * n, MPI_CHAR, from, comm);
  MPI_Bcast(p.X.data(), 3, MPI_DOUBLE, from, comm);
}

void set_nodes(const Problem& problem, const int32_t* local, int n, MaterialPoint& p) {
  const Distribution& dist = problem.distribution();
  p.nodes.clear();
  p.free_dofs.clear();
  for (int a = 0; a < n; ++a) {
    p.nodes.push_back(dist.local_nodes[local[a]]);
    for (int d = 0; d < 3; ++d) p.free_dofs.push_back(!problem.constrained(3 * local[a] + d));
  }
}

}  // namespace

bool locate(const Problem& problem, const std::array<double, 3>& X, MaterialPoint& point) {
  const Distribution& dist = problem.distribution();
  const int npe = dist.nodes_per_tet();
  const std::vector<double>& x = dist.x;
  struct {
    double value;
    int rank;
  } best{-1e300, dist.rank};
  int64_t best_tet = -1;
  Eigen::Vector3d best_xi;
  for (size_t t = 0; t < dist.local_tets.size(); ++t) {
    const int32_t* tet = &dist.tet_nodes[t * npe];
    Eigen::Matrix3d A;
    Eigen::Vector3d x0(x[3 * tet[0]], x[3 * tet[0] + 1], x[3 * tet[0] + 2]);
    for (int k = 1; k <= 3; ++k)
      for (int d = 0; d < 3; ++d) A(d, k - 1) = x[3 * tet[k] + d] - x0(d);
    const Eigen::Vector3d xi = A.partialPivLu().solve(Eigen::Vector3d(X[0], X[1], X[2]) - x0);
    const double smallest = std::min({1 - xi.sum(), xi(0), xi(1), xi(2)});
    if (smallest > best.value) {  // the most inside tetrahedron (robust on shared faces)
      best.value = smallest;
      best_tet = static_cast<int64_t>(t);
      best_xi = xi;
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, &best, 1, MPI_DOUBLE_INT, MPI_MAXLOC, problem.comm());
  if (best.value < -1e-9) return false;
  if (best.rank == dist.rank) {
    auto best_tet_nodes = [&](int a) { return dist.tet_nodes[best_tet * npe + a]; };
    set_nodes(problem, &dist.tet_nodes[best_tet * npe], npe, point);
    point.N.resize(npe);
    tet_shape(dist.order, best_xi, point.N.data(), nullptr);
    for (int d = 0; d < 3; ++d) {  // sum_a N_a X_a: X itself unless a P2 edge is curved
      point.X[d] = 0;
      for (int a = 0; a < npe; ++a) point.X[d] += point.N[a] * x[3 * best_tet_nodes(a) + d];
    }
  }
  share(point, best.rank, problem.comm());
  return true;
}

MaterialPoint group_point(const Problem& problem, const std::string& group) {
  const Distribution& dist = problem.distribution();
  MaterialPoint p;
  int owner = -1;
  const auto it = dist.node_groups.find(group);
  if (it != dist.node_groups.end())
    for (int32_t l : it->second)
      if (l < dist.num_owned()) {
        owner = dist.rank;
        set_nodes(problem, &l, 1, p);
        p.N = {1.0};
        for (int d = 0; d < 3; ++d) p.X[d] = dist.x[3 * l + d];
      }
  MPI_Allreduce(MPI_IN_PLACE, &owner, 1, MPI_INT, MPI_MAX, problem.comm());
  if (owner < 0) throw std::logic_error("group_point: group '" + group + "' has no node");
  share(p, owner, problem.comm());
  return p;
}

Effectors::Effectors(const Config& config, Problem& problem) : problem_(problem) {
  if (!config.control) return;
  const MeshGroups& groups = problem.distribution().groups;
  for (const auto& e : config.control->effectors) {
    MaterialPoint p;
    const std::string where = config.deck_path + ": control.effectors '" + e.name + "'";
    names_.push_back(e.name);
    configs_.push_back(e);
    obstacle_.push_back(-1);
    between_.push_back({-1, -1});
    only_.emplace_back();
    approach_gap_.push_back(0);
    if (!e.between.empty()) {  // the deck parser checked the names and contact.self
      const auto& surfaces = config.contact.surfaces;
      for (int k = 0; k < 2; ++k)
        between_.back()[k] = static_cast<int>(
            std::find(surfaces.begin(), surfaces.end(), e.between[k]) - surfaces.begin());
      if (!problem.self_contact()) throw InputError(where + ": between needs contact.self: true");
      for (int d = 0; d < 3; ++d) {
        reference_.push_back(0);
        rows_.push_back(problem.create_vector());
      }
      continue;
    }
    if (!e.obstacle.empty()) {  // the deck parser checked the names
      for (size_t o = 0; o < config.obstacles.size(); ++o)
        if (config.obstacles[o].name == e.obstacle) obstacle_.back() = static_cast<int>(o);
      if (obstacle_.back() < 0 || !problem.contact())
        throw InputError(where + ": obstacle '" + e.obstacle + "' is not in contact with the body");
      const Distribution& dist = problem.distribution();
      if (!e.surfaces.empty()) only_.back().assign(dist.x.size() / 3, 0);
      for (const auto& group : e.surfaces) {
        const auto it = dist.faces.find(group);
        if (it != dist.faces.end())
          for (int32_t n : it->second) only_.back()[n] = 1;
      }
      for (int d = 0; d < 3; ++d) {
        reference_.push_back(0);
        rows_.push_back(problem.create_vector());
      }
      continue;
    }
    if (!e.point.empty()) {
      auto it = groups.group_nodes.find(e.point);
      if (it == groups.group_nodes.end() || it->second != 1)
        throw InputError(where + ": point group '" + e.point + "' must hold exactly one node (" +
                         (it == groups.group_nodes.end() ? std::string("not in the mesh")
                                                         : std::to_string(it->second) + " nodes") +
                         ")");
      p = group_point(problem, e.point);
    } else if (!locate(problem, e.position, p)) {
      throw InputError(where + ": position (" + std::to_string(e.position[0]) + ", " +
                       std::to_string(e.position[1]) + ", " + std::to_string(e.position[2]) +
                       ") lies outside the mesh");
    }
    for (int d = 0; d < 3; ++d) reference_.push_back(p.X[d]);
    append_point_rows(problem, p.nodes, p.N, rows_);
  }
}

void append_point_rows(Problem& problem, const std::vector<int64_t>& nodes,
                       const std::vector<double>& N, VecArray& rows) {
  const Distribution& dist = problem.distribution();
  for (int d = 0; d < 3; ++d) {
    VecHandle row(problem.create_vector());
    if (dist.rank == 0)
      for (size_t a = 0; a < nodes.size(); ++a)
        HS_PETSC(VecSetValue(row, static_cast<PetscInt>(3 * nodes[a] + d), N[a], ADD_VALUES));
    HS_PETSC(VecAssemblyBegin(row));
    HS_PETSC(VecAssemblyEnd(row));
    rows.push_back(row.release());
  }
}

int Effectors::index(const std::string& name) const {
  for (size_t e = 0; e < names_.size(); ++e)
    if (names_[e] == name) return static_cast<int>(e);
  return -1;
}

const std::vector<char>* Effectors::only(size_t e) const {
  return only_[e].empty() ? nullptr : &only_[e];
}

std::vector<double> Effectors::positions(Vec u) const {
  std::vector<double> x(reference_);
  for (size_t e = 0; e < names_.size(); ++e) {
    if (is_force(e)) {  // the obstacles stand where the load factor 1 puts them
      const std::array<double, 3> f =
          obstacle_[e] >= 0 ? problem_.contact_force(u, 1.0, obstacle_[e], only(e))
                            : problem_.self_contact_force(u, between_[e][0], between_[e][1]);
      std::copy(f.begin(), f.end(), &x[3 * e]);
      continue;
    }
    for (int d = 0; d < 3; ++d) {
      PetscScalar dot = 0;
      HS_PETSC(VecDot(rows_[3 * e + d], u, &dot));
      x[3 * e + d] += dot;
    }
  }
  return x;
}

void Effectors::linearize(Vec u) {
  for (size_t e = 0; e < names_.size(); ++e)
    if (obstacle_[e] >= 0)
      approach_gap_[e] =
          problem_.contact_force_rows(u, 1.0, obstacle_[e], only(e), &rows_.data()[3 * e]);
    else if (between_[e][0] >= 0)
      approach_gap_[e] =
          problem_.self_contact_force_rows(u, between_[e][0], between_[e][1], &rows_.data()[3 * e]);
}

}  // namespace hs
