// The column method (CPU reference) against independent references: the paper's Table I, the
// exact volumes of polyhedra, the weight identity, and invariances of the fill rule.
#include <gtest/gtest.h>

#include <cmath>

#include "support.hpp"

namespace fw = fluidweight;
using namespace fwtest;

namespace {

const auto kReference = fw::Implementation::cpu_reference;

Result run(const SurfaceMesh& mesh, int n, Vec3 gravity = {0.0, -9.81, 0.0}) {
  return fw::compute(mesh, options(kReference, n, gravity));
}

double norm(Vec3 v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

}  // namespace

// Seed paper, Table I: the 5120-triangle icosphere of radius 1 cm.
TEST(ColumnReference, PaperSphereVolumes) {
  SurfaceMesh sphere = fw::shapes::icosphere(4);
  ASSERT_EQ(sphere.num_triangles(), 5120);
  EXPECT_NEAR(volume(sphere), 4.17974, 5e-6);
  const std::pair<int, double> table[] = {
      {30, 4.1835}, {50, 4.1828}, {100, 4.1804}, {200, 4.1799}, {500, 4.1798}};
  for (auto [n, paper] : table) {
    Result r = run(sphere, n);
    EXPECT_NEAR(r.column_volume, paper, 1.5e-4) << "grid " << n;
    EXPECT_EQ(r.unmatched_columns, 0);
  }
}

// The weight of the liquid equals rho |g| times the column volume, at every grid, for shapes of
// every character (total weight = sum of the sections' weights, to round-off).
TEST(ColumnReference, TotalWeightIsRhoGTimesColumnVolume) {
  std::vector<SurfaceMesh> meshes = {
      fw::shapes::icosphere(3),          fw::shapes::torus(1, 0.3, 40, 16), e_shape(), comb(5),
      fw::shapes::uneven_sphere(3, 6.0), box({2.0, 0.02, 1.0}, 2)};
  for (size_t m = 0; m < meshes.size(); ++m) {
    for (int n : {1, 2, 7, 30, 64, 101}) {
      Result r = run(meshes[m], n);
      EXPECT_NEAR(r.total_weight, 1000 * 9.81 * r.column_volume,
                  1e-12 * 1000 * 9.81 * std::fabs(r.signed_volume) + 1e-12)
          << "mesh " << m << " grid " << n;
      EXPECT_EQ(r.unmatched_columns, 0) << "mesh " << m << " grid " << n;
      Vec3 f = total_force(r);
      EXPECT_NEAR(f[0], 0.0, 1e-9 * r.total_weight);
      EXPECT_NEAR(f[2], 0.0, 1e-9 * r.total_weight);
      EXPECT_NEAR(f[1], -r.total_weight, 1e-12 * r.total_weight);
    }
  }
}

// The column volume tends to the signed volume as N grows, on odd and even grids.
TEST(ColumnReference, ConvergesToSignedVolume) {
  std::vector<SurfaceMesh> meshes = {fw::shapes::icosphere(4), fw::shapes::torus(1, 0.25, 64, 24),
                                     fw::shapes::torus(1, 0.25, 64, 24),
                                     fw::shapes::uneven_sphere(4, 8.0)};
  // A torus standing on its rim: columns cross it twice.
  meshes[2] = transformed(meshes[2], rotation({1, 0, 0}, 1.5707963267948966));
  for (size_t c = 0; c < meshes.size(); ++c) {
    double exact = volume(meshes[c]);
    for (int parity : {0, 1}) {
      double err50 = std::fabs(run(meshes[c], 50 + parity).column_volume - exact) / exact;
      double err400 = std::fabs(run(meshes[c], 400 + parity).column_volume - exact) / exact;
      EXPECT_LT(err400, err50 / 4) << "mesh " << c << " parity " << parity;
      EXPECT_LT(err400, 1e-4) << "mesh " << c << " parity " << parity;
    }
  }
}

// Voxel shapes whose voxels are whole numbers of columns: every column lies entirely inside or
// outside each voxel, so the column volume is exact, although column centres lie on the
// diagonals of the horizontal faces (both triangles of a face touch them: the fill rule must
// count each once) and on vertical walls.
TEST(ColumnReference, VoxelShapesAreExactWhenColumnsAlign) {
  SurfaceMesh e = e_shape();  // 5 x 5 x 3 voxels: columns along y, grid over (z, x) = 3 x 5
  const double exact = volume(e);
  EXPECT_DOUBLE_EQ(exact, 17 * 3);  // 17 voxels a layer (3 arms of 5, 2 bar voxels), 3 layers
  for (int n : {15, 30, 60}) {
    // The grid is square (N x N) over a 3 x 5 box: cells are 3/N by 5/N, so voxels are whole
    // cells when N is a multiple of 15.
    Result r = run(e, n);
    EXPECT_NEAR(r.column_volume, exact, 1e-12 * exact) << "grid " << n;
    EXPECT_EQ(r.unmatched_columns, 0);
  }
  SurfaceMesh cube = box({1, 1, 1}, 4);
  for (int n : {4, 8, 12, 40}) EXPECT_NEAR(run(cube, n).column_volume, 1.0, 1e-12);
}

// Column centres exactly on a vertex and on shared edges of one layer: an octahedron centred
// on a column centre (odd N) has its top and bottom vertices and the projections of four
// shared edges on column centres. Any double count or gap changes the volume by a column.
TEST(ColumnReference, VerticesOnColumnCentres) {
  for (int n : {5, 9, 31, 32, 101}) {
    SurfaceMesh o = octahedron({0, 0, 0}, 1.0);
    Result r = run(o, n);
    EXPECT_EQ(r.unmatched_columns, 0);
    // Midpoint-rule volume of the octahedron on this grid, summed column by column.
    double w = 2.0 / n, expected = 0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        double x = -1 + (i + 0.5) * w, z = -1 + (j + 0.5) * w;
        double h = 2 * std::max(0.0, 1 - std::fabs(x) - std::fabs(z));
        expected += h * w * w;
      }
    }
    EXPECT_NEAR(r.column_volume, expected, 1e-12) << "grid " << n;
  }
}

// Reversing every triangle (inward orientation) changes nothing but the signed volume's sign.
TEST(ColumnReference, EitherOrientation) {
  for (const SurfaceMesh& m : {fw::shapes::torus(1, 0.3, 30, 12), e_shape()}) {
    Result out = run(m, 37), in = run(flipped(m), 37);
    EXPECT_NEAR(in.signed_volume, -out.signed_volume, 1e-12);
    EXPECT_NEAR(in.column_volume, out.column_volume, 1e-12 * out.column_volume);
    EXPECT_LT(force_difference(in, out), 1e-12);
  }
}

// The grid follows the mesh: translating it, shuffling its triangles or starting them at other
// corners gives the same columns, volume and forces.
TEST(ColumnReference, TranslationAndShuffleInvariance) {
  SurfaceMesh m = transformed(fw::shapes::icosphere(3), rotation({1, 2, 3}, 0.4));
  Result base = run(m, 64);
  Result moved = run(translated(m, {3.5, -12.25, 100.0}), 64);
  Result mixed = run(shuffled(m, 7), 64);
  EXPECT_NEAR(moved.column_volume, base.column_volume, 1e-11 * base.column_volume);
  EXPECT_NEAR(mixed.column_volume, base.column_volume, 1e-13 * base.column_volume);
  EXPECT_LT(force_difference(moved, base), 1e-9);
  EXPECT_LT(force_difference(mixed, base), 1e-12);
}

// Gravity along any direction: rotating mesh and gravity by a quarter turn about an axis maps
// the grid onto itself, so volume and forces rotate exactly; an arbitrary rotation changes
// the grid but not the limit, and the forces stay along gravity.
TEST(ColumnReference, GravityAlongAnyDirection) {
  SurfaceMesh m = transformed(e_shape(), rotation({1, 1, 0}, 0.3));
  Result base = run(m, 45);
  for (Vec3 axis : {Vec3{1, 0, 0}, Vec3{0, 0, 1}}) {
    Mat3 q = rotation(axis, 1.5707963267948966);
    Vec3 g = apply(q, {0, -9.81, 0});
    Result r = run(transformed(m, q), 45, g);
    EXPECT_NEAR(r.column_volume, base.column_volume, 1e-9 * base.column_volume);
    EXPECT_NEAR(r.total_weight, base.total_weight, 1e-9 * base.total_weight);
    Vec3 f = total_force(r);
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(f[d] / norm(f), g[d] / 9.81, 1e-12);
  }
  Vec3 g{3.0, -5.0, 7.5};
  SurfaceMesh sphere = fw::shapes::icosphere(4);
  Result r = run(sphere, 400, g);
  EXPECT_NEAR(r.column_volume, volume(sphere), 2e-4 * volume(sphere));
  Vec3 f = total_force(r);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(f[d] / norm(f), g[d] / norm(g), 1e-12);
}

// Vertical triangles cover no column; the voxel shapes are all vertical walls and flat faces.
// A thin slab (1/50 of its width) is exact at any grid; a thin fin (1/50 of the width) on a
// base is exact when columns align with it and within one row of columns otherwise.
TEST(ColumnReference, ThinFeatures) {
  EXPECT_NEAR(run(box({1.0, 0.02, 1.0}, 1), 3).column_volume, 0.02, 1e-15);
  const int nx = 50, ny = 6, nz = 4;
  std::vector<bool> occ(nx * ny * nz, false);
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) occ[(k * ny + j) * nx + i] = j == 0 || i == 3;
    }
  }
  // x in [0, 1], y in [0, 0.6], z in [0, 1]; the fin is x in [0.06, 0.08], 0.5 high.
  SurfaceMesh finned = fw::shapes::voxels(nx, ny, nz, occ, {0.02, 0.1, 0.25});
  const double exact = volume(finned);
  EXPECT_NEAR(exact, 0.1 + 0.02 * 0.5, 1e-14);
  for (int n : {50, 100}) EXPECT_NEAR(run(finned, n).column_volume, exact, 1e-13);
  for (int n : {7, 37, 301}) {
    Result r = run(finned, n);
    EXPECT_LE(std::fabs(r.column_volume - exact), 0.5 / n) << "grid " << n;
    EXPECT_EQ(r.unmatched_columns, 0);
  }
}

// column_head on three stacked arms (the "E"): every floor and ceiling carries the liquid's
// pressure at its depth below the top, as the closed form's vertical components do; the
// paper's column method leaves the lower arms' ceilings unloaded and puts the head on no wall.
// Both weigh the same in total.
TEST(ColumnHead, FloorsAndCeilingsCarryThePressureAtTheirDepth) {
  const SurfaceMesh e = e_shape();
  Options head = options(kReference, 200);
  head.method = fw::Method::column_head;
  Options closed = options(kReference, 1);
  closed.method = fw::Method::hydrostatic;
  const Result h = fw::compute(e, head), c = fw::compute(e, closed), paper = run(e, 200);
  double largest = 0, head_error = 0, paper_error = 0;
  for (int v = 0; v < e.num_vertices(); ++v) {
    largest = std::max(largest, std::fabs(c.forces[3 * v + 1]));
    head_error = std::max(head_error, std::fabs(h.forces[3 * v + 1] - c.forces[3 * v + 1]));
    paper_error = std::max(paper_error, std::fabs(paper.forces[3 * v + 1] - c.forces[3 * v + 1]));
    EXPECT_EQ(h.forces[3 * v], 0.0);  // vertical only: the side walls' push is left out
  }
  EXPECT_LT(head_error, 0.01 * largest) << head_error / largest;
  EXPECT_GT(paper_error, 0.3 * largest) << paper_error / largest;
  const double weight = 1000 * 9.81 * std::fabs(volume(e));
  EXPECT_NEAR(total_force(h)[1], -weight, 1e-3 * weight);
  EXPECT_NEAR(total_force(h)[1], total_force(paper)[1], 1e-12 * weight);
  EXPECT_EQ(h.column_volume, paper.column_volume);
}

// A column's weight, the size of a jump of the weights: rho g times a column's cross-section
// times the cavity's height (here 5 x 3 columns' box over N^2, height 5), none in closed form.
TEST(ColumnHead, ColumnWeightIsOneColumnOfTheCavitysHeight) {
  const SurfaceMesh e = e_shape();
  const Result paper = run(e, 100);
  EXPECT_NEAR(paper.column_weight, 1000 * 9.81 * (5.0 * 3.0 / (100 * 100)) * 5.0,
              0.02 * paper.column_weight);
  Options closed = options(kReference, 100);
  closed.method = fw::Method::hydrostatic;
  EXPECT_EQ(fw::compute(e, closed).column_weight, 0.0);
}
