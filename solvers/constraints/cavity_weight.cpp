#include "solvers/constraints/cavity_weight.hpp"

#include <petscis.h>

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "solvers/petsc_check.hpp"

namespace hs {

CavityTriangles cavity_triangles(const Mesh& mesh, const std::string& group) {
  const auto& faces = mesh.surfaces.at(group);
  CavityTriangles t;
  t.nodes.assign(faces.begin(), faces.end());
  std::sort(t.nodes.begin(), t.nodes.end());
  t.nodes.erase(std::unique(t.nodes.begin(), t.nodes.end()), t.nodes.end());
  auto index = [&](int64_t node) {
    return static_cast<int>(std::lower_bound(t.nodes.begin(), t.nodes.end(), node) -
                            t.nodes.begin());
  };
  const int npf = mesh.nodes_per_face();
  // Tri6 (vertices 0-2, edge nodes 3:(0,1) 4:(1,2) 5:(2,0)): four triangles of the same
  // orientation, so every node, edge nodes included, receives its share.
  static const int kSplit[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};
  for (size_t f = 0; f < faces.size() / npf; ++f) {
    const int64_t* face = &faces[f * npf];
    if (npf == 3) {
      for (int a = 0; a < 3; ++a) t.triangles.push_back(index(face[a]));
    } else {
      for (const auto& tri : kSplit)
        for (int a : tri) t.triangles.push_back(index(face[a]));
    }
  }
  return t;
}

CavityWeight::CavityWeight(const Mesh& mesh, const Distribution& dist, const CavityConfig& cavity,
                           const std::array<double, 3>& gravity, int owner, MPI_Comm comm)
    : comm_(comm), owner_(owner), density_(cavity.density) {
  MPI_Comm_rank(comm, &rank_);
  const auto& fw = cavity.fluid_weight;
  options_.method = fw.method == WeightMethod::hydrostatic ? fluidweight::Method::hydrostatic
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

  const CavityTriangles tris = cavity_triangles(mesh, cavity.group);
  const auto n = static_cast<PetscInt>(tris.nodes.size());
  std::vector<PetscInt> from;
  if (rank_ == owner_) {
    for (int64_t node : tris.nodes)
      for (int d = 0; d < 3; ++d) {
        from.push_back(static_cast<PetscInt>(3 * dist.new_of_old[node] + d));
        reference_.push_back(mesh.x[3 * node + d]);
      }
    positions_ = reference_;
    global_dofs_ = from;
    fluidweight::SurfaceMesh surface;
    surface.vertices = reference_;
    surface.triangles = tris.triangles;
    context_ = std::make_unique<fluidweight::Context>(options_);
    context_->set_cavities({surface});
  }
  (void)n;
  HS_PETSC(VecCreateSeq(PETSC_COMM_SELF, static_cast<PetscInt>(global_dofs_.size()), &surface_u_));
}

CavityWeight::~CavityWeight() {
  VecScatterDestroy(&gather_);
  VecDestroy(&surface_u_);
}

const char* CavityWeight::device() const {
  return options_.method == fluidweight::Method::hydrostatic            ? "cpu"
         : options_.implementation == fluidweight::Implementation::cuda ? "cuda"
                                                                        : "cpu";
}

void CavityWeight::add_weight(Vec u, double load_factor, Vec W) {
  const double t0 = MPI_Wtime();
  if (!gather_) {  // set up against the first u: every u shares the problem's layout
    IS is_from;
    HS_PETSC(ISCreateGeneral(PETSC_COMM_SELF, static_cast<PetscInt>(global_dofs_.size()),
                             global_dofs_.data(), PETSC_COPY_VALUES, &is_from));
    HS_PETSC(VecScatterCreate(u, is_from, surface_u_, nullptr, &gather_));
    HS_PETSC(ISDestroy(&is_from));
  }
  HS_PETSC(VecScatterBegin(gather_, u, surface_u_, INSERT_VALUES, SCATTER_FORWARD));
  HS_PETSC(VecScatterEnd(gather_, u, surface_u_, INSERT_VALUES, SCATTER_FORWARD));

  double summary[2] = {0, 0};  // total weight, measured volume
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
  }
  HS_PETSC(VecAssemblyBegin(W));
  HS_PETSC(VecAssemblyEnd(W));
  MPI_Bcast(summary, 2, MPI_DOUBLE, owner_, comm_);
  total_weight_ = summary[0];
  volume_ = summary[1];
  seconds_ = MPI_Wtime() - t0;
}

}  // namespace hs
