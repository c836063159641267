// The CUDA kernels against the CPU reference: every kernel in float64 and float32, on shapes
// of every character, one cavity or a batch, fixed or moving vertices. Skipped, with a message,
// where there is no CUDA device (CI); they must pass on a GPU machine.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "support.hpp"

namespace fw = fluidweight;
using namespace fwtest;

namespace {

#define SKIP_WITHOUT_GPU()                                                                  \
  if (!fw::cuda_available()) {                                                              \
    GTEST_SKIP() << "no CUDA device here (or the module was built without CUDA): the CUDA " \
                    "tests run on a GPU machine";                                           \
  }

struct Variant {
  fw::Kernel kernel;
  fw::Precision precision;
};

std::string name(const Variant& v) {
  return fw::to_string(v.kernel) + "_" + fw::to_string(v.precision);
}

Options cuda_options(const Variant& v, int n, Vec3 gravity = {0, -9.81, 0}) {
  Options o = options(fw::Implementation::cuda, n, gravity);
  o.kernel = v.kernel;
  o.precision = v.precision;
  return o;
}

// Volume and forces against the reference, within the precision's round-off.
void expect_matches_reference(const Result& gpu, const Result& ref, fw::Precision p,
                              const std::string& what) {
  const bool f64 = p == fw::Precision::float64;
  EXPECT_NEAR(gpu.column_volume, ref.column_volume,
              (f64 ? 1e-12 : 2e-6) * std::fabs(ref.signed_volume))
      << what;
  EXPECT_NEAR(gpu.signed_volume, ref.signed_volume, 1e-12 * std::fabs(ref.signed_volume)) << what;
  EXPECT_EQ(gpu.unmatched_columns, 0) << what;
  EXPECT_LT(force_difference(gpu, ref), f64 ? 1e-10 : 2e-4) << what;
  // float32: nodal weights are sums of many float atomics.
  EXPECT_NEAR(gpu.total_weight, ref.total_weight, (f64 ? 1e-11 : 2e-5) * ref.total_weight) << what;
  EXPECT_GE(gpu.timings.gpu_ms, 0.0);
}

class CudaKernels : public testing::TestWithParam<Variant> {};

}  // namespace

TEST_P(CudaKernels, MatchReferenceOnVariedShapes) {
  SKIP_WITHOUT_GPU();
  const Variant v = GetParam();
  struct Case {
    std::string label;
    SurfaceMesh mesh;
  };
  std::vector<Case> cases = {
      {"sphere", fw::shapes::icosphere(4)},
      {"standing torus", transformed(fw::shapes::torus(1, 0.25, 64, 24), rotation({1, 0, 0}, 1.3))},
      {"E shape", transformed(e_shape(), rotation({1, 1, 0}, 0.3))},
      {"comb of 9", comb(9)},  // 18 hits in a column: more than the first buffers hold
      {"uneven sphere", fw::shapes::uneven_sphere(4, 12.0)},
      {"octahedron", octahedron({0, 0, 0}, 1)},
      {"inward torus", flipped(fw::shapes::torus(1, 0.4, 40, 16))}};
  for (const Case& c : cases) {
    for (int n : {1, 31, 64, 200, 401}) {
      Result ref = fw::compute(c.mesh, options(fw::Implementation::cpu_reference, n));
      Result gpu = fw::compute(c.mesh, cuda_options(v, n));
      expect_matches_reference(gpu, ref, v.precision, c.label + " grid " + std::to_string(n));
    }
  }
}

TEST_P(CudaKernels, GravityAlongAnyDirection) {
  SKIP_WITHOUT_GPU();
  const Variant v = GetParam();
  SurfaceMesh m = transformed(fw::shapes::torus(1, 0.3, 48, 20), rotation({0.2, 1, 0.4}, 0.8));
  for (Vec3 g : {Vec3{0, 0, -9.81}, Vec3{3, -5, 7.5}, Vec3{-1, 0, 0}}) {
    Result ref = fw::compute(m, options(fw::Implementation::cpu_reference, 150, g));
    expect_matches_reference(fw::compute(m, cuda_options(v, 150, g)), ref, v.precision, "gravity");
  }
}

// Four cavities in one call (the paper's pendulum) against separate reference calls; then the
// same context with moved vertices, as in a control loop.
TEST_P(CudaKernels, BatchAndMovingVertices) {
  SKIP_WITHOUT_GPU();
  const Variant v = GetParam();
  std::vector<SurfaceMesh> cavities = {fw::shapes::icosphere(3), e_shape(),
                                       translated(fw::shapes::torus(1, 0.3, 30, 12), {5, 0, 0}),
                                       fw::shapes::uneven_sphere(3, 6.0)};
  fw::Context context(cuda_options(v, 200));
  context.set_cavities(cavities);
  for (int step = 0; step < 3; ++step) {
    std::vector<SurfaceMesh> moved;
    std::vector<const double*> positions;
    for (const SurfaceMesh& c : cavities) {
      moved.push_back(transformed(c, rotation({1, 2, 3}, 0.2 * step)));
    }
    for (const SurfaceMesh& c : moved) positions.push_back(c.vertices.data());
    context.set_positions(positions);
    const std::vector<Result>& results = context.compute();
    ASSERT_EQ(results.size(), cavities.size());
    for (size_t c = 0; c < cavities.size(); ++c) {
      Result ref = fw::compute(moved[c], options(fw::Implementation::cpu_reference, 200));
      expect_matches_reference(results[c], ref, v.precision,
                               "cavity " + std::to_string(c) + " step " + std::to_string(step));
    }
  }
  std::vector<double> replays = context.time_device_replays(5);
  ASSERT_EQ(replays.size(), 5u);
  for (double ms : replays) EXPECT_GT(ms, 0.0);
}

// column_head: each section's floor and the ceiling above it both carry the head from the
// liquid's top (resolve.cuh), against the CPU reference's; stacked chambers (the E shape's
// arms, the comb's teeth) are where it differs from the paper's method.
TEST_P(CudaKernels, ColumnHeadMatchesReference) {
  SKIP_WITHOUT_GPU();
  const Variant v = GetParam();
  const std::vector<std::pair<std::string, SurfaceMesh>> cases = {
      {"E shape", transformed(e_shape(), rotation({1, 1, 0}, 0.3))},
      {"comb of 9", comb(9)},
      {"standing torus", transformed(fw::shapes::torus(1, 0.25, 64, 24), rotation({1, 0, 0}, 1.3))},
      {"inward torus", flipped(fw::shapes::torus(1, 0.4, 40, 16))}};
  for (const auto& [label, mesh] : cases) {
    for (int n : {31, 200}) {
      Options ref_options = options(fw::Implementation::cpu_reference, n);
      ref_options.method = fw::Method::column_head;
      Options gpu_options = cuda_options(v, n);
      gpu_options.method = fw::Method::column_head;
      const Result ref = fw::compute(mesh, ref_options);
      const Result paper = fw::compute(mesh, options(fw::Implementation::cpu_reference, n));
      // The case loads ceilings at all: the head's forces are not the paper's.
      EXPECT_GT(force_difference(paper, ref), 1e-3) << label;
      expect_matches_reference(fw::compute(mesh, gpu_options), ref, v.precision,
                               label + " column_head grid " + std::to_string(n));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllKernels, CudaKernels,
    testing::Values(Variant{fw::Kernel::leveraging, fw::Precision::float64},
                    Variant{fw::Kernel::leveraging, fw::Precision::float32},
                    Variant{fw::Kernel::triangle_parallel, fw::Precision::float64},
                    Variant{fw::Kernel::triangle_parallel, fw::Precision::float32},
                    Variant{fw::Kernel::tiled, fw::Precision::float64},
                    Variant{fw::Kernel::tiled, fw::Precision::float32},
                    Variant{fw::Kernel::fused, fw::Precision::float64},
                    Variant{fw::Kernel::fused, fw::Precision::float32}),
    [](const testing::TestParamInfo<Variant>& info) { return name(info.param); });

// Tiles of 8 and 16 columns, and a tile list that must grow (a coarse mesh at a fine grid
// has triangles over many tiles; a fine mesh at a coarse grid many triangles a tile).
TEST(Cuda, TiledKernelTileSizesAndGrowth) {
  SKIP_WITHOUT_GPU();
  SurfaceMesh fine = fw::shapes::icosphere(5);  // 20480 triangles
  SurfaceMesh coarse = fw::shapes::icosphere(1);
  for (int tile : {8, 16}) {
    for (const SurfaceMesh* m : {&fine, &coarse}) {
      for (int n : {20, 300}) {
        Options o = cuda_options({fw::Kernel::tiled, fw::Precision::float64}, n);
        o.tile = tile;
        Result ref = fw::compute(*m, options(fw::Implementation::cpu_reference, n));
        expect_matches_reference(fw::compute(*m, o), ref, fw::Precision::float64,
                                 "tile " + std::to_string(tile) + " grid " + std::to_string(n));
      }
    }
  }
}

// The tiled kernel's tiles taken heaviest first, in the order the previous call's counts give
// (order_kernel), which it does from one and a half waves of blocks on: a batch of three
// cavities (no comb: its float64 volume sums over 480^2 columns differ from the reference's
// by more than the 1e-12 bound in rounding alone) at 480^2 (2700 tiles of 16 columns, 10800 of 8:
// over 1.5 waves of the most blocks a GPU of up to 132 SMs holds, 8 and 32 an SM) whose vertices
// move, so that each call's order comes from other counts; and one cavity at 900^2.
TEST(Cuda, TiledKernelHeaviestTilesFirst) {
  SKIP_WITHOUT_GPU();
  const int n = 480;
  const std::vector<SurfaceMesh> cavities = {
      fw::shapes::uneven_sphere(4, 12.0), translated(fw::shapes::torus(1, 0.3, 30, 12), {4, 0, 0}),
      translated(fw::shapes::icosphere(3), {0, 0, 4})};
  std::vector<std::vector<SurfaceMesh>> moved(3);
  std::vector<std::vector<Result>> refs(3);
  for (int step = 0; step < 3; ++step) {
    for (const SurfaceMesh& c : cavities) {
      moved[step].push_back(transformed(c, rotation({1, 2, 3}, 0.4 * step)));
      refs[step].push_back(
          fw::compute(moved[step].back(), options(fw::Implementation::cpu_reference, n)));
    }
  }
  for (int tile : {8, 16}) {
    for (fw::Precision p : {fw::Precision::float64, fw::Precision::float32}) {
      Options o = cuda_options({fw::Kernel::tiled, p}, n);
      o.tile = tile;
      fw::Context context(o);
      context.set_cavities(cavities);
      for (int step = 0; step < 3; ++step) {
        std::vector<const double*> positions;
        for (const SurfaceMesh& m : moved[step]) positions.push_back(m.vertices.data());
        context.set_positions(positions);
        const std::vector<Result>& results = context.compute();
        for (size_t c = 0; c < cavities.size(); ++c) {
          expect_matches_reference(results[c], refs[step][c], p,
                                   "tile " + std::to_string(tile) + " cavity " + std::to_string(c) +
                                       " step " + std::to_string(step));
        }
      }
    }
  }
  SurfaceMesh sphere = fw::shapes::icosphere(4);
  Result ref = fw::compute(sphere, options(fw::Implementation::cpu_reference, 900));
  for (fw::Precision p : {fw::Precision::float64, fw::Precision::float32}) {
    expect_matches_reference(fw::compute(sphere, cuda_options({fw::Kernel::tiled, p}, 900)), ref, p,
                             "grid 900");
  }
}

// Every column kernel assumes each cavity's orientation from the previous call (checked after
// it), and the fused kernel keeps two sets of accumulators: graph replays between calls (an
// odd number of them), moving vertices, a cavity turned inside out (mirrored: its signed volume
// changes sign) and back, for fused, tiled and leveraging; for fused also tiles of 8 and 16
// columns, and a list of a tile's triangles that must grow.
TEST(Cuda, AssumedOrientationAcrossCallsAndReplays) {
  SKIP_WITHOUT_GPU();
  const std::vector<SurfaceMesh> cavities = {
      fw::shapes::icosphere(4), translated(fw::shapes::torus(1, 0.3, 30, 12), {4, 1, 0}),
      flipped(fw::shapes::icosphere(2)), comb(5)};
  auto mirrored = [](const SurfaceMesh& m) {
    SurfaceMesh r = m;
    for (size_t k = 0; k < r.vertices.size(); k += 3) r.vertices[k] = -r.vertices[k];
    return r;
  };
  for (fw::Kernel kernel : {fw::Kernel::fused, fw::Kernel::tiled, fw::Kernel::leveraging}) {
    for (fw::Precision p : {fw::Precision::float64, fw::Precision::float32}) {
      for (int n : {7, 200}) {
        fw::Context context(cuda_options({kernel, p}, n));
        context.set_cavities(cavities);
        for (int step = 0; step < 5; ++step) {
          std::vector<SurfaceMesh> moved;
          for (size_t c = 0; c < cavities.size(); ++c) {
            SurfaceMesh m = transformed(cavities[c], rotation({1, 2, 3}, 0.3 * step));
            // Cavity 1 is mirrored at steps 2 and 3: the orientation flips twice.
            moved.push_back(c == 1 && (step == 2 || step == 3) ? mirrored(m) : m);
          }
          std::vector<const double*> positions;
          for (const SurfaceMesh& m : moved) positions.push_back(m.vertices.data());
          context.set_positions(positions);
          const std::vector<Result>& results = context.compute();
          for (size_t c = 0; c < cavities.size(); ++c) {
            Result ref = fw::compute(moved[c], options(fw::Implementation::cpu_reference, n));
            expect_matches_reference(results[c], ref, p,
                                     "kernel " + std::to_string(static_cast<int>(kernel)) +
                                         " grid " + std::to_string(n) + " cavity " +
                                         std::to_string(c) + " step " + std::to_string(step));
          }
          EXPECT_EQ(context.time_device_replays(step + 1).size(), static_cast<size_t>(step + 1));
        }
      }
    }
  }
  // Tiles of 8 and 16 columns; a fine mesh whose tiles keep more triangles than the first list
  // holds.
  SurfaceMesh fine = fw::shapes::icosphere(5);
  for (int tile : {8, 16}) {
    for (int n : {20, 300}) {
      Result ref = fw::compute(fine, options(fw::Implementation::cpu_reference, n));
      Options o = cuda_options({fw::Kernel::fused, fw::Precision::float64}, n);
      o.tile = tile;
      expect_matches_reference(fw::compute(fine, o), ref, fw::Precision::float64,
                               "tile " + std::to_string(tile) + " grid " + std::to_string(n));
    }
  }
}

// automatic: the tiled kernel for a small cavity (1280 triangles at 150^2), leveraging for a
// fine mesh on a coarse grid (81920 triangles, about one column each at 150^2), the tiled one
// for a large cavity on a fine grid (the same at 400^2); all right.
TEST(Cuda, AutomaticKernel) {
  SKIP_WITHOUT_GPU();
  const std::pair<SurfaceMesh, int> cases[] = {{fw::shapes::icosphere(3), 150},
                                               {fw::shapes::icosphere(6), 150},
                                               {fw::shapes::icosphere(6), 400}};
  for (const auto& [m, n] : cases) {
    Result ref = fw::compute(m, options(fw::Implementation::cpu_reference, n));
    Result gpu = fw::compute(m, cuda_options({fw::Kernel::automatic, fw::Precision::float64}, n));
    expect_matches_reference(gpu, ref, fw::Precision::float64, "automatic");
  }
}

TEST(Cuda, HydrostaticMatchesCpu) {
  SKIP_WITHOUT_GPU();
  for (fw::Precision p : {fw::Precision::float64, fw::Precision::float32}) {
    for (Vec3 g : {Vec3{0, -9.81, 0}, Vec3{1, 2, -3}}) {
      SurfaceMesh m = translated(e_shape(), {1, 2, 3});
      Options cpu = options(fw::Implementation::cpu_reference, 1, g);
      cpu.method = fw::Method::hydrostatic;
      Options gpu = cpu;
      gpu.implementation = fw::Implementation::cuda;
      gpu.precision = p;
      Result a = fw::compute(m, cpu), b = fw::compute(m, gpu);
      EXPECT_LT(force_difference(b, a), p == fw::Precision::float64 ? 1e-12 : 1e-5);
      EXPECT_NEAR(b.total_weight, a.total_weight, 1e-5 * a.total_weight);
    }
  }
}
