// Problem: pressure surfaces of cavities and what constraints measure on them.
#include <stdexcept>

#include "solvers/problem.hpp"

namespace hs {

int Problem::add_cavity_surface(const std::string& group) {
  if (pattern_fixed_)
    throw std::logic_error("Problem::add_cavity_surface after the tangent's matrix was created");
  PressureSurface s;
  s.value = 0;
  s.scaled = false;
  auto it = dist_.faces.find(group);
  if (it != dist_.faces.end()) s.faces = it->second;
  pressure_faces_.push_back(std::move(s));
  return static_cast<int>(pressure_faces_.size()) - 1;
}

double Problem::enclosed_volume(int surface, Vec u) {
  LocalView view(u, u_work_);
  const PetscScalar* ua = view.values();
  const int npf = dist_.nodes_per_face();
  const auto& faces = pressure_faces_[surface].faces;
  double local = 0, xf[18];
  for (size_t f = 0; f < faces.size() / npf; ++f) {
    const int32_t* nodes = &faces[f * npf];
    for (int k = 0; k < 3 * npf; ++k)
      xf[k] = X_[3 * nodes[k / 3] + k % 3] + ua[3 * nodes[k / 3] + k % 3];
    local += face_enclosed_volume(dist_.order, xf);
  }
  double total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return total;
}

void Problem::volume_gradient(int surface, Vec u, Vec g) {
  assemble_local(u, g, [&](const PetscScalar* ua, PetscScalar* ra) {
    const int npf = dist_.nodes_per_face();
    const auto& faces = pressure_faces_[surface].faces;
    double xf[18], ff[18];
    for (size_t f = 0; f < faces.size() / npf; ++f) {
      const int32_t* nodes = &faces[f * npf];
      for (int k = 0; k < 3 * npf; ++k)
        xf[k] = X_[3 * nodes[k / 3] + k % 3] + ua[3 * nodes[k / 3] + k % 3];
      face_pressure(dist_.order, xf, 1.0, ff, nullptr);
      for (int k = 0; k < 3 * npf; ++k) ra[3 * nodes[k / 3] + k % 3] += ff[k];
    }
  });
  dofs_.zero(g);
}

void Problem::cavity_pressure_load(Vec u, Vec f) {
  // As assemble_forces adds them, so that external_load minus this is the rest exactly.
  assemble_local(u, f, [&](const PetscScalar* ua, PetscScalar* ra) {
    const int npf = dist_.nodes_per_face();
    double xf[18], ff[18];
    for (const auto& surface : pressure_faces_) {
      if (surface.scaled) continue;  // a deck's pressure load, not a cavity's
      for (size_t k = 0; k < surface.faces.size() / npf; ++k) {
        const int32_t* nodes = &surface.faces[k * npf];
        for (int i = 0; i < 3 * npf; ++i)
          xf[i] = X_[3 * nodes[i / 3] + i % 3] + ua[3 * nodes[i / 3] + i % 3];
        face_pressure(dist_.order, xf, surface.value, ff, nullptr);
        for (int i = 0; i < 3 * npf; ++i) ra[3 * nodes[i / 3] + i % 3] += ff[i];
      }
    }
  });
}

std::array<double, 3> Problem::area_vector(const std::string& group, Vec u) {
  std::array<double, 3> local{0, 0, 0}, total{0, 0, 0};
  auto it = dist_.faces.find(group);
  if (it != dist_.faces.end()) {
    LocalView view(u, u_work_);
    const PetscScalar* ua = view.values();
    const int npf = dist_.nodes_per_face();
    double xf[18], ff[18];
    for (size_t f = 0; f < it->second.size() / npf; ++f) {
      const int32_t* nodes = &it->second[f * npf];
      for (int k = 0; k < 3 * npf; ++k)
        xf[k] = X_[3 * nodes[k / 3] + k % 3] + ua[3 * nodes[k / 3] + k % 3];
      face_pressure(dist_.order, xf, -1.0, ff, nullptr);  // f_a = int N_a n da
      for (int k = 0; k < 3 * npf; ++k) local[k % 3] += ff[k];
    }
  }
  MPI_Allreduce(local.data(), total.data(), 3, MPI_DOUBLE, MPI_SUM, comm_);
  return total;
}

std::array<double, 3> Problem::mean_displacement(const std::string& group, Vec u) {
  // int u dA = sum_a u_a int N_a dA, exact for u in the face's space; int N_a dA is the
  // nodal force of a unit dead traction.
  double local[4] = {0, 0, 0, 0}, total[4];
  auto it = dist_.faces.find(group);
  if (it != dist_.faces.end()) {
    LocalView view(u, u_work_);
    const PetscScalar* ua = view.values();
    const int npf = dist_.nodes_per_face();
    double Xf[18], weights[18];
    for (size_t f = 0; f < it->second.size() / npf; ++f) {
      const int32_t* nodes = &it->second[f * npf];
      for (int k = 0; k < 3 * npf; ++k) Xf[k] = X_[3 * nodes[k / 3] + k % 3];
      face_traction(dist_.order, Xf, {1.0, 1.0, 1.0}, weights);
      for (int a = 0; a < npf; ++a) {
        for (int d = 0; d < 3; ++d) local[d] += weights[3 * a] * ua[3 * nodes[a] + d];
        local[3] += weights[3 * a];
      }
    }
  }
  MPI_Allreduce(local, total, 4, MPI_DOUBLE, MPI_SUM, comm_);
  if (!(total[3] > 0)) return {0, 0, 0};
  return {total[0] / total[3], total[1] / total[3], total[2] / total[3]};
}

}  // namespace hs
