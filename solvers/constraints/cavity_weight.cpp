#include "solvers/constraints/cavity_weight.hpp"

#include <petscis.h>

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "solvers/petsc_check.hpp"

namespace hs {

std::vector<int> cavity_triangles(const GatheredSurface& surface) {
  const std::vector<int>& faces = surface.faces;
  std::vector<int> t;
  const int npf = surface.nodes_per_face;
  // Tri6 (vertices 0-2, edge nodes 3:(0,1) 4:(1,2) 5:(2,0)): four triangles of the same
  // orientation, so every node, edge nodes included, receives its share.
  static const int kSplit[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};
  for (size_t f = 0; f < faces.size() / npf; ++f) {
    const int* face = &faces[f * npf];
    if (npf == 3) {
      for (int a = 0; a < 3; ++a) t.push_back(face[a]);
    } else {
      for (const auto& tri : kSplit)
        for (int a : tri) t.push_back(face[a]);
    }
  }
  return t;
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
    fluidweight::SurfaceMesh surface;
    surface.vertices = reference_;
    surface.triangles = cavity_triangles(walls);
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
    context_->set_positions({positions_.data()});
    const fluidweight::Result& r = context_->compute().front();
    std::vector<PetscScalar> f(r.forces.size());
    for (size_t k = 0; k < f.size(); ++k) f[k] = load_factor * r.forces[k];
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
