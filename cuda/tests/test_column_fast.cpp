// The multithreaded CPU fast path gives the reference's columns, volumes and nodal forces.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support.hpp"

namespace fw = fluidweight;
using namespace fwtest;

namespace {

void expect_same(const SurfaceMesh& mesh, int n, int threads, Vec3 gravity = {0, -9.81, 0},
                 double volume_tolerance = 1e-12, fw::CpuKernels kernels = fw::CpuKernels::widest) {
  Options ref = options(fw::Implementation::cpu_reference, n, gravity);
  Options fast = options(fw::Implementation::cpu_fast, n, gravity);
  fast.threads = threads;
  fast.cpu_kernels = kernels;
  Result a = fw::compute(mesh, ref), b = fw::compute(mesh, fast);
  EXPECT_NEAR(b.column_volume, a.column_volume, volume_tolerance * std::fabs(a.signed_volume))
      << "grid " << n << " threads " << threads;
  EXPECT_NEAR(b.signed_volume, a.signed_volume, 1e-12 * std::fabs(a.signed_volume));
  EXPECT_EQ(b.unmatched_columns, 0);
  EXPECT_LT(force_difference(b, a), 1e-11) << "grid " << n << " threads " << threads;
}

std::string kernel_name(fw::CpuKernels kernels) {
  return kernels == fw::CpuKernels::portable ? "portable"
         : kernels == fw::CpuKernels::avx2   ? "avx2"
                                             : "widest";
}

}  // namespace

TEST(ColumnFast, MatchesReferenceOnVariedShapes) {
  std::vector<SurfaceMesh> meshes = {
      fw::shapes::icosphere(4),
      transformed(fw::shapes::torus(1, 0.3, 48, 20), rotation({1, 0.2, 0}, 1.2)),
      e_shape(),
      comb(9),  // 9 sections per column: more hits than a column's buffer keeps
      fw::shapes::uneven_sphere(3, 10.0),
      octahedron({0, 0, 0}, 1.0)};
  for (size_t m = 0; m < meshes.size(); ++m) {
    SCOPED_TRACE("mesh " + std::to_string(m));
    for (int n : {1, 15, 31, 64, 255}) {
      for (int threads : {1, 3}) expect_same(meshes[m], n, threads);
    }
  }
}

TEST(ColumnFast, InwardOrientationAndOtherGravity) {
  SurfaceMesh m = flipped(transformed(e_shape(), rotation({0.3, 1, 0.1}, 0.7)));
  expect_same(m, 90, 2, {1.0, 2.0, -3.0});
  expect_same(fw::shapes::torus(1, 0.4, 40, 16), 77, 2, {0, 0, -9.81});
}

// A context computes again with new positions (same connectivity), as a control loop does.
TEST(ColumnFast, ContextFollowsMovingVertices) {
  SurfaceMesh a = fw::shapes::icosphere(3);
  SurfaceMesh b = transformed(a, rotation({1, 1, 1}, 0.5));
  for (size_t v = 0; v < b.vertices.size(); ++v) b.vertices[v] *= 1.0 + 0.1 * (v % 3);
  Options o = options(fw::Implementation::cpu_fast, 120);
  fw::Context context(o);
  context.set_cavities({a});
  Result first = context.compute().front();
  context.set_positions({b.vertices.data()});
  Result second = context.compute().front();
  EXPECT_NEAR(first.column_volume, fw::compute(a, o).column_volume, 1e-13);
  EXPECT_NEAR(second.column_volume, fw::compute(b, o).column_volume, 1e-13);
  EXPECT_LT(force_difference(second, fw::compute(b, o)), 1e-13);
}

// Step 2 assumes each cavity's orientation to be the one its previous call found: a cavity
// turned inside out (mirrored: its signed volume changes sign) and back within one context,
// beside a cavity that keeps its orientation, with every kernel level.
TEST(ColumnFast, ContextFollowsCavityTurnedInsideOut) {
  const std::vector<SurfaceMesh> cavities = {
      translated(fw::shapes::torus(1, 0.3, 30, 12), {4, 1, 0}), flipped(fw::shapes::icosphere(2))};
  auto mirrored = [](const SurfaceMesh& m) {
    SurfaceMesh r = m;
    for (size_t k = 0; k < r.vertices.size(); k += 3) r.vertices[k] = -r.vertices[k];
    return r;
  };
  for (fw::CpuKernels kernels :
       {fw::CpuKernels::portable, fw::CpuKernels::avx2, fw::CpuKernels::widest}) {
    const std::string level = kernel_name(kernels);
    for (int threads : {1, 2}) {
      Options o = options(fw::Implementation::cpu_fast, 70);
      o.threads = threads;
      o.cpu_kernels = kernels;
      fw::Context context(o);
      context.set_cavities(cavities);
      for (int step = 0; step < 5; ++step) {
        std::vector<SurfaceMesh> moved;
        for (size_t c = 0; c < cavities.size(); ++c) {
          SurfaceMesh m = transformed(cavities[c], rotation({1, 2, 3}, 0.3 * step));
          // Cavity 0 is mirrored at steps 1 and 2, cavity 1 at step 3.
          const bool mirror = c == 0 ? step == 1 || step == 2 : step == 3;
          moved.push_back(mirror ? mirrored(m) : m);
        }
        context.set_positions({moved[0].vertices.data(), moved[1].vertices.data()});
        const std::vector<Result>& results = context.compute();
        for (size_t c = 0; c < cavities.size(); ++c) {
          SCOPED_TRACE("kernels " + level + " threads " + std::to_string(threads) + " step " +
                       std::to_string(step) + " cavity " + std::to_string(c));
          Result ref = fw::compute(moved[c], options(fw::Implementation::cpu_reference, 70));
          EXPECT_NEAR(results[c].signed_volume, ref.signed_volume,
                      1e-12 * std::fabs(ref.signed_volume));
          EXPECT_NEAR(results[c].column_volume, ref.column_volume,
                      1e-12 * std::fabs(ref.signed_volume));
          EXPECT_EQ(results[c].unmatched_columns, 0);
          EXPECT_LT(force_difference(results[c], ref), 1e-11);
        }
      }
    }
  }
}

TEST(ColumnFast, BatchEqualsSeparateCalls) {
  std::vector<SurfaceMesh> cavities = {fw::shapes::icosphere(3), e_shape(),
                                       translated(fw::shapes::torus(1, 0.3, 30, 12), {5, 0, 0})};
  Options o = options(fw::Implementation::cpu_fast, 64);
  std::vector<Result> batch = fw::compute_batch(cavities, o);
  ASSERT_EQ(batch.size(), cavities.size());
  for (size_t c = 0; c < cavities.size(); ++c) {
    Result alone = fw::compute(cavities[c], o);
    // Bands are shared among the threads dynamically: sums differ in order only.
    EXPECT_NEAR(batch[c].column_volume, alone.column_volume, 1e-14 * alone.column_volume);
    EXPECT_LT(force_difference(batch[c], alone), 1e-13);
  }
}

// Triangles taller than the rows rasterized at once (and than a band of rows), and wide ones,
// at fine grids. The reference sums the column heights one after the other: at 600^2 its own
// rounding reaches 2e-12 of the volume (against a long double sum), hence the tolerance.
TEST(ColumnFast, TallAndWideTrianglesAtFineGrids) {
  SurfaceMesh m = translated(transformed(e_shape(), rotation({1, 0, 1}, 0.25)), {0.3, -2, 1});
  for (int n : {300, 600}) {
    for (int threads : {1, 2}) expect_same(m, n, threads, {0, -9.81, 0}, 1e-11);
  }
}

// The portable kernels (taken where the processor has no AVX2) and the AVX2 ones (taken where
// it has AVX2 but not AVX-512) against the reference, on the machine
// that runs the tests whatever it has (a level it lacks falls back to a narrower one).
TEST(ColumnFast, NarrowerKernelsMatchReference) {
  std::vector<SurfaceMesh> meshes = {
      fw::shapes::icosphere(4), e_shape(), comb(9), fw::shapes::uneven_sphere(3, 10.0),
      translated(transformed(e_shape(), rotation({1, 0, 1}, 0.25)), {0.3, -2, 1})};
  for (fw::CpuKernels kernels : {fw::CpuKernels::portable, fw::CpuKernels::avx2}) {
    for (size_t m = 0; m < meshes.size(); ++m) {
      SCOPED_TRACE("kernels " + kernel_name(kernels) + " mesh " + std::to_string(m));
      for (int n : {15, 64, 255}) {
        for (int threads : {1, 3})
          expect_same(meshes[m], n, threads, {0, -9.81, 0}, 1e-12, kernels);
      }
    }
    expect_same(meshes.back(), 600, 2, {0, -9.81, 0}, 1e-11, kernels);
  }
}

// The total weight is the length of the forces' sum, taken without squaring it: near 1e161 N
// (a density of 1e160) its square would overflow to infinity.
TEST(ColumnFast, TotalWeightOfHugeForcesIsFinite) {
  for (auto implementation : {fw::Implementation::cpu_reference, fw::Implementation::cpu_fast}) {
    Options o = options(implementation, 64, {0, -9.81, 0});
    o.rho = 1e160;
    const Result r = fw::compute(fw::shapes::icosphere(3), o);
    ASSERT_TRUE(std::isfinite(r.total_weight));
    EXPECT_NEAR(r.total_weight, 1e160 * 9.81 * r.column_volume, 1e-12 * r.total_weight);
  }
}
