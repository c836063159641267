// Steps 3-5 as the paper lays them out: a raster kernel that tests column-triangle candidates
// and writes each hit to its column's slots in global memory, then one thread per column that
// pairs the hits (column_kernel).
//
// leveraging_kernel is Algorithm 1: with c the average number of candidate columns per
// triangle box, k = max(1, floor(alpha c)) threads share each triangle, thread `id` taking the
// triangle's candidates id mod k, id mod k + k, ... in one launch of k n threads (run here as a
// grid-stride loop over those virtual threads, since k is known only on the device).
// triangle_parallel_kernel is the baseline: one thread walks a whole box.
#include <cub/block/block_reduce.cuh>

#include "resolve.cuh"

namespace fluidweight::detail::gpu {
namespace {

constexpr int kBlock = 256;

// Steps 3-4 for one candidate: a hit goes to its column's next slot.
template <typename Real>
__device__ inline void test_candidate(const Batch<Real>& b, const DevTri<Real>& t, int tri, int i,
                                      int j, int sub_bits) {
  int64_t e[3];
  if (!covers_column(t, column_centre(i, sub_bits), column_centre(j, sub_bits), e)) return;
  const size_t columns = static_cast<size_t>(b.num_cavities) * b.n * b.n;
  const size_t col = (static_cast<size_t>(cavity_of(t.flags)) * b.n + j) * b.n + i;
  int slot = atomicAdd(&b.column_count[col], 1);
  if (slot < b.column_capacity) {
    b.column_z[slot * columns + col] = height_at(t, e);
    b.column_tag[slot * columns + col] = is_floor(t.flags) ? ~tri : tri;
  }
}

template <typename Real>
__global__ void __launch_bounds__(kBlock) leveraging_kernel(Batch<Real> b) {
  using Reduce = cub::BlockReduce<unsigned long long, kBlock>;
  __shared__ typename Reduce::TempStorage storage;
  __shared__ unsigned long long candidates;
  unsigned long long sum = 0;
  for (int k = threadIdx.x; k < b.setup_blocks; k += blockDim.x) sum += b.candidates[k];
  sum = Reduce(storage).Sum(sum);
  if (threadIdx.x == 0) candidates = sum;
  __syncthreads();
  const double c = static_cast<double>(candidates) / b.num_triangles;
  const long long k = max(1ll, static_cast<long long>(floor(b.alpha * c)));
  const long long threads = k * b.num_triangles;
  const long long stride = static_cast<long long>(gridDim.x) * blockDim.x;
  for (long long id = blockIdx.x * blockDim.x + threadIdx.x; id < threads; id += stride) {
    const int tri = static_cast<int>(id / k);
    const DevTri<Real> t = load_tri(&b.tris[tri]);
    const int width = t.i1 - t.i0 + 1, height = t.j1 - t.j0 + 1;
    if (width <= 0 || height <= 0) continue;
    const int sub_bits = b.cavities[cavity_of(t.flags)].grid.sub_bits;
    for (long long cur = id % k; cur < static_cast<long long>(width) * height; cur += k) {
      int i = t.i0 + static_cast<int>(cur % width);
      int j = t.j0 + static_cast<int>((cur / width) % height);
      test_candidate(b, t, tri, i, j, sub_bits);
    }
  }
}

template <typename Real>
__global__ void __launch_bounds__(kBlock) triangle_parallel_kernel(Batch<Real> b) {
  const int tri = blockIdx.x * blockDim.x + threadIdx.x;
  if (tri >= b.num_triangles) return;
  const DevTri<Real> t = load_tri(&b.tris[tri]);
  if (t.i0 > t.i1 || t.j0 > t.j1) return;
  const int sub_bits = b.cavities[cavity_of(t.flags)].grid.sub_bits;
  for (int j = t.j0; j <= t.j1; ++j) {
    for (int i = t.i0; i <= t.i1; ++i) test_candidate(b, t, tri, i, j, sub_bits);
  }
}

// Step 5, one thread per column; resets the column's count for the next call.
template <typename Real>
__global__ void __launch_bounds__(kBlock) column_kernel(Batch<Real> b) {
  using Reduce = cub::BlockReduce<double, kBlock>;
  using ReduceCount = cub::BlockReduce<unsigned, kBlock>;
  __shared__ typename Reduce::TempStorage storage;
  __shared__ typename ReduceCount::TempStorage count_storage;
  __shared__ int block_cavity[2];
  const size_t per_cavity = static_cast<size_t>(b.n) * b.n;
  const size_t columns = per_cavity * b.num_cavities;
  const size_t col = static_cast<size_t>(blockIdx.x) * blockDim.x + threadIdx.x;
  int n = 0, cavity = b.num_cavities - 1, i = 0, j = 0;
  if (col < columns) {
    cavity = static_cast<int>(col / per_cavity);
    size_t local = col % per_cavity;
    j = static_cast<int>(local / b.n);
    i = static_cast<int>(local % b.n);
    n = b.column_count[col];
    if (n) {
      b.column_count[col] = 0;
      if (n > b.column_capacity) {
        atomicMax(&b.status->max_column_hits, n);
        n = b.column_capacity;
      }
    }
  }
  // A block may straddle two cavities: each lane uses its own cavity's grid.
  const GridParams& grid = b.cavities[cavity].grid;
  double sum_heights = 0.0;
  unsigned unmatched = 0;
  ColumnHits<Real> hits{b.column_z + col, b.column_tag + col, static_cast<int>(columns)};
  resolve_column(b, hits, n, i, j, grid, sum_heights, unmatched, GlobalFloors<Real>{b});
  // Per-cavity sums, for each cavity the block's columns belong to (usually one).
  if (threadIdx.x == 0) block_cavity[0] = cavity;
  if (threadIdx.x == blockDim.x - 1) block_cavity[1] = cavity;
  __syncthreads();
  for (int c = block_cavity[0]; c <= block_cavity[1]; ++c) {
    bool mine = cavity == c;
    double s = Reduce(storage).Sum(mine ? sum_heights : 0.0);
    unsigned u = ReduceCount(count_storage).Sum(mine ? unmatched : 0u);
    if (threadIdx.x == 0) {
      const int stripe = blockIdx.x % kStripes;
      if (s != 0.0) atomicAdd(&b.cavities[c].sum_heights[stripe], s);
      if (u) atomicAdd(&b.cavities[c].unmatched[stripe], static_cast<unsigned long long>(u));
    }
    __syncthreads();
  }
}

}  // namespace

template <typename Real>
void launch_raster(const Batch<Real>& b, bool leveraging, int num_sms, cudaStream_t stream) {
  if (leveraging) {
    leveraging_kernel<Real><<<num_sms * 8, kBlock, 0, stream>>>(b);
  } else {
    int blocks = (b.num_triangles + kBlock - 1) / kBlock;
    triangle_parallel_kernel<Real><<<blocks, kBlock, 0, stream>>>(b);
  }
}

template <typename Real>
void launch_columns(const Batch<Real>& b, cudaStream_t stream) {
  size_t columns = static_cast<size_t>(b.num_cavities) * b.n * b.n;
  unsigned blocks = static_cast<unsigned>((columns + kBlock - 1) / kBlock);
  column_kernel<Real><<<blocks, kBlock, 0, stream>>>(b);
}

template void launch_raster<float>(const Batch<float>&, bool, int, cudaStream_t);
template void launch_raster<double>(const Batch<double>&, bool, int, cudaStream_t);
template void launch_columns<float>(const Batch<float>&, cudaStream_t);
template void launch_columns<double>(const Batch<double>&, cudaStream_t);

}  // namespace fluidweight::detail::gpu
