// Grid-free alternative: the hydrostatic pressure of the liquid integrated in closed form.
//
// p = rho |g| d, with d the depth below the cavity's highest vertex, is linear over each flat
// triangle, so its consistent nodal forces are exact: with vertex pressures p_1..p_3 and
// N = (x_2 - x_1) x (x_3 - x_1) oriented outward, f_i = N (p_i + p_1 + p_2 + p_3) / 24 (the
// integral of the hat function of node i times p n). Summed over a closed surface the forces
// equal rho g V, and their moment equals rho V x_c x g (x_c the centroid), exactly: the
// divergence theorem applied to the linear pressure field.
#include "cpu.hpp"

namespace fluidweight::detail {

void hydrostatic(const CavityView& cavity, const Frame& frame, const GridParams& grid, double rho_g,
                 CavityOutput& out) {
  out.values.assign(3 * static_cast<size_t>(cavity.num_vertices), 0.0);
  out.unmatched_columns = 0;
  for (int t = 0; t < cavity.num_triangles; ++t) {
    const int* v = cavity.triangles + 3 * t;
    Vec3 x[3];
    double p[3];
    for (int k = 0; k < 3; ++k) {
      x[k] = load_vec3(cavity.xyz, v[k]);
      p[k] = rho_g * (grid.u1 - dot_rn(x[k], frame.up));
    }
    double ux = x[1].x - x[0].x, uy = x[1].y - x[0].y, uz = x[1].z - x[0].z;
    double wx = x[2].x - x[0].x, wy = x[2].y - x[0].y, wz = x[2].z - x[0].z;
    double s = grid.orientation / 24.0;
    double nx = s * (uy * wz - uz * wy), ny = s * (uz * wx - ux * wz), nz = s * (ux * wy - uy * wx);
    double sum = p[0] + p[1] + p[2];
    for (int k = 0; k < 3; ++k) {
      double q = p[k] + sum;
      out.values[3 * v[k]] += nx * q;
      out.values[3 * v[k] + 1] += ny * q;
      out.values[3 * v[k] + 2] += nz * q;
    }
  }
}

}  // namespace fluidweight::detail
