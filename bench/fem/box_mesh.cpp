// The cantilever's box (0.1 x 0.01 x 0.01 m, x from 0, y and z centred) as a hydrosoft mesh
// file, for the benchmarks at sizes gmsh would take minutes to mesh: NX x NY x NZ cubes of 6
// tetrahedra each (the 6 around the diagonal from the cube's low corner to its high one),
// groups body (volume), clamped (the faces at x = 0) and bottom (the faces at z = -H/2, where
// the beam lands on a floor: bench/contact/cantilever_on_floor.yaml).
//   box_mesh NX NY NZ OUT.h5
#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "mesh/mesh.hpp"
#include "mesh/mesh_h5.hpp"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: box_mesh NX NY NZ OUT.h5\n");
    return 2;
  }
  const int64_t nx = std::atoll(argv[1]), ny = std::atoll(argv[2]), nz = std::atoll(argv[3]);
  const double L = 0.1, H = 0.01;
  hs::Mesh m;
  auto node = [&](int64_t i, int64_t j, int64_t k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int64_t k = 0; k <= nz; ++k)
    for (int64_t j = 0; j <= ny; ++j)
      for (int64_t i = 0; i <= nx; ++i) {
        m.x.push_back(L * i / nx);
        m.x.push_back(H * j / ny - H / 2);
        m.x.push_back(H * k / nz - H / 2);
      }
  // Corners of a cube by bits (x: 1, y: 2, z: 4); each tetrahedron goes 0 -> a -> a|b -> 7.
  static const int kPaths[6][2] = {{1, 2}, {1, 4}, {2, 1}, {2, 4}, {4, 1}, {4, 2}};
  m.tets.reserve(24 * nx * ny * nz);
  for (int64_t k = 0; k < nz; ++k)
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i) {
        auto corner = [&](int c) { return node(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1)); };
        for (const auto& p : kPaths) {
          std::array<int64_t, 4> t = {corner(0), corner(p[0]), corner(p[0] | p[1]), corner(7)};
          double a[3][3];
          for (int r = 0; r < 3; ++r)
            for (int d = 0; d < 3; ++d) a[r][d] = m.x[3 * t[r + 1] + d] - m.x[3 * t[0] + d];
          const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                             a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                             a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
          if (det < 0) std::swap(t[2], t[3]);
          m.tets.insert(m.tets.end(), t.begin(), t.end());
        }
      }
  m.tet_volume.assign(m.num_tets(), 0);
  m.volume_names = {"body"};
  std::vector<int64_t>& body = m.node_groups["body"];
  for (int64_t n = 0; n < m.num_nodes(); ++n) body.push_back(n);
  // A face group and its node group: the faces of tetrahedra with all three nodes on the
  // plane coordinate `axis` = `at`, oriented out of the body.
  static const int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};  // outward
  auto add_group = [&m](const std::string& name, int axis, double at) {
    auto on = [&](int64_t n) { return m.x[3 * n + axis] == at; };
    std::vector<int64_t>& faces = m.surfaces[name];
    std::vector<int64_t>& bounds = m.surface_tets[name];
    for (int64_t t = 0; t < m.num_tets(); ++t)
      for (const auto& f : kFace) {
        const int64_t a = m.tets[4 * t + f[0]], b = m.tets[4 * t + f[1]], c = m.tets[4 * t + f[2]];
        if (on(a) && on(b) && on(c)) {
          faces.insert(faces.end(), {a, b, c});
          bounds.push_back(t);
        }
      }
    std::vector<int64_t>& nodes = m.node_groups[name];
    for (int64_t n = 0; n < m.num_nodes(); ++n)
      if (on(n)) nodes.push_back(n);
  };
  add_group("clamped", 0, 0.0);
  add_group("bottom", 2, -H / 2);
  hs::write_mesh_h5(m, argv[4]);
  std::printf("{\"nodes\": %lld, \"tets\": %lld, \"dofs\": %lld}\n",
              static_cast<long long>(m.num_nodes()), static_cast<long long>(m.num_tets()),
              static_cast<long long>(3 * m.num_nodes()));
  return 0;
}
