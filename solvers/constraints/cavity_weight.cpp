#include "solvers/constraints/cavity_weight.hpp"

#include <petscis.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

#include "common/error.hpp"
#include "solvers/petsc_check.hpp"

namespace hs {

namespace {

// Tri6 shape functions at barycentric (l0, l1, l2): vertices 0-2, edge nodes 3:(0,1) 4:(1,2)
// 5:(2,0).
std::array<double, 6> tri6_shape(double l0, double l1, double l2) {
  return {l0 * (2 * l0 - 1), l1 * (2 * l1 - 1), l2 * (2 * l2 - 1),
          4 * l0 * l1,       4 * l1 * l2,       4 * l2 * l0};
}

}  // namespace

WallTriangulation wall_triangulation(const GatheredSurface& surface, int n) {
  WallTriangulation w;
  const std::vector<int>& faces = surface.faces;
  const int npf = surface.nodes_per_face;
  const size_t num_faces = faces.size() / npf;
  if (npf == 3) {
    w.num_points = static_cast<int>(surface.x.size() / 3);
    w.triangles = faces;
    for (int p = 0; p < w.num_points; ++p) w.terms.push_back({p, p, 1.0});
    return w;
  }
  if (n < 2) throw std::invalid_argument("wall_triangulation: n must be >= 2 on Tri6 faces");
  // A point of a face at lattice coordinates (i, j, k), i + j + k = n, over its vertices
  // (a, b, c): the same point of a neighbouring face has the same nonzero (vertex, count)
  // pairs, whatever the faces' orders.
  std::map<std::vector<std::pair<int, int>>, int> point_of;
  auto point = [&](const int* face, int i, int j, int k) {
    std::vector<std::pair<int, int>> key;
    for (const auto& [vertex, count] : {std::pair{face[0], i}, {face[1], j}, {face[2], k}})
      if (count > 0) key.emplace_back(vertex, count);
    std::sort(key.begin(), key.end());
    const auto [it, added] = point_of.emplace(key, w.num_points);
    if (added) {
      const std::array<double, 6> shape = tri6_shape(double(i) / n, double(j) / n, double(k) / n);
      for (int a = 0; a < 6; ++a)
        if (shape[a] != 0) w.terms.push_back({w.num_points, face[a], shape[a]});
      ++w.num_points;
    }
    return it->second;
  };
  for (size_t f = 0; f < num_faces; ++f) {
    const int* face = &faces[f * npf];
    // (s, t) = (j, k) / n runs over the face as (0,0), (1,0), (0,1) run over vertices 0, 1,
    // 2: triangles counter-clockwise in (s, t) keep the face's orientation.
    auto at = [&](int j, int k) { return point(face, n - j - k, j, k); };
    for (int k = 0; k < n; ++k)
      for (int j = 0; j + k < n; ++j) {
        for (int p : {at(j, k), at(j + 1, k), at(j, k + 1)}) w.triangles.push_back(p);
        if (j + k + 2 <= n)
          for (int p : {at(j + 1, k), at(j + 1, k + 1), at(j, k + 1)}) w.triangles.push_back(p);
      }
  }
  return w;
}

void WallTriangulation::points_of(const std::vector<double>& nodes,
                                  std::vector<double>& points) const {
  points.assign(3 * static_cast<size_t>(num_points), 0.0);
  for (const Term& t : terms)
    for (int d = 0; d < 3; ++d) points[3 * t.point + d] += t.weight * nodes[3 * t.node + d];
}

void WallTriangulation::node_forces(const std::vector<double>& points, size_t num_nodes,
                                    std::vector<double>& nodes) const {
  nodes.assign(3 * num_nodes, 0.0);
  for (const Term& t : terms)
    for (int d = 0; d < 3; ++d) nodes[3 * t.node + d] += t.weight * points[3 * t.point + d];
}

CavityWeight::CavityWeight(const Distribution& dist, const CavityConfig& cavity,
                           const std::array<double, 3>& gravity, int owner, MPI_Comm comm)
    : comm_(comm), owner_(owner), density_(cavity.density) {
  MPI_Comm_rank(comm, &rank_);
  const auto& fw = cavity.fluid_weight;
  options_.method = fw.method == WeightMethod::hydrostatic   ? fluidweight::Method::hydrostatic
                    : fw.method == WeightMethod::column_head ? fluidweight::Method::column_head
                                                             : fluidweight::Method::column;
  options_.implementation = fw.device == WeightDevice::cuda ? fluidweight::Implementation::cuda
                                                            : fluidweight::Implementation::cpu_fast;
  options_.grid = fw.grid;
  options_.rho = cavity.density;
  options_.threads = 1;  // one core per rank: the ranks already share the machine
  options_.gravity = gravity;
  gravity_norm_ =
      std::sqrt(gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2]);

  // Decided on the owning rank and shared, so that every rank stops together.
  int no_gpu = 0;
  if (rank_ == owner_)
    no_gpu = options_.implementation == fluidweight::Implementation::cuda &&
             !fluidweight::cuda_available();
  MPI_Bcast(&no_gpu, 1, MPI_INT, owner_, comm_);
  if (no_gpu)
    throw InputError("cavity '" + cavity.group +
                     "': fluid_weight.device is cuda, but this build has no CUDA or the machine "
                     "no GPU (use device: cpu)");

  const GatheredSurface walls = gather_surface(dist, cavity.group, owner_, comm_);
  if (rank_ == owner_) {
    for (int64_t node : walls.global_nodes)
      for (int d = 0; d < 3; ++d) global_dofs_.push_back(static_cast<PetscInt>(3 * node + d));
    reference_ = walls.x;
    positions_ = reference_;
    walls_ = wall_triangulation(walls, fw.subdivision);
    fluidweight::SurfaceMesh surface;
    walls_.points_of(reference_, surface.vertices);
    surface.triangles = walls_.triangles;
    context_ = std::make_unique<fluidweight::Context>(options_);
    context_->set_cavities({surface});
  }
  HS_PETSC(
      VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(global_dofs_.size()), surface_u_.out()));
}

const char* CavityWeight::device() const {
  return options_.method == fluidweight::Method::hydrostatic            ? "cpu"
         : options_.implementation == fluidweight::Implementation::cuda ? "cuda"
                                                                        : "cpu";
}

void CavityWeight::add_weight(Vec u, double load_factor, Vec W) {
  const double t0 = MPI_Wtime();
  if (!gather_) {  // set up against the first u: every u shares the problem's layout
    IsHandle is_from;
    HS_PETSC(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(global_dofs_.size()),
                             global_dofs_.data(), PETSC_COPY_VALUES, is_from.out()));
    HS_PETSC(VecScatterCreate(u, is_from, surface_u_, nullptr, gather_.out()));
  }
  HS_PETSC(VecScatterBegin(gather_, u, surface_u_, INSERT_VALUES, SCATTER_FORWARD));
  HS_PETSC(VecScatterEnd(gather_, u, surface_u_, INSERT_VALUES, SCATTER_FORWARD));

  double summary[3] = {0, 0, 0};  // total weight, measured volume, one column's weight
  if (rank_ == owner_) {
    const PetscScalar* su;
    HS_PETSC(VecGetArrayRead(surface_u_, &su));
    for (size_t k = 0; k < positions_.size(); ++k) positions_[k] = reference_[k] + su[k];
    HS_PETSC(VecRestoreArrayRead(surface_u_, &su));
    walls_.points_of(positions_, points_);
    context_->set_positions({points_.data()});
    const fluidweight::Result& r = context_->compute().front();
    std::vector<double> f;
    walls_.node_forces(r.forces, positions_.size() / 3, f);
    for (double& fk : f) fk *= load_factor;
    if (load_factor != 0)
      HS_PETSC(VecSetValues(W, static_cast<PetscInt>(f.size()), global_dofs_.data(), f.data(),
                            ADD_VALUES));
    summary[0] = std::abs(load_factor) * r.total_weight;
    summary[1] = r.column_volume;
    summary[2] = std::abs(load_factor) * r.column_weight;
  }
  HS_PETSC(VecAssemblyBegin(W));
  HS_PETSC(VecAssemblyEnd(W));
  MPI_Bcast(summary, 3, MPI_DOUBLE, owner_, comm_);
  total_weight_ = summary[0];
  volume_ = summary[1];
  column_weight_ = summary[2];
  seconds_ = MPI_Wtime() - t0;
}

}  // namespace hs
