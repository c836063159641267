// Steps 3-5 as the paper lays them out: a raster kernel that tests column-triangle candidates
// and writes each hit to its column's slots in global memory, then one thread per column that
// pairs the hits (column_kernel).
//
// leveraging_kernel is Algorithm 1: with c the average number of candidate columns per
// triangle box, k = max(1, floor(alpha c)) threads share each triangle, thread `id` taking the
// triangle's candidates id mod k, id mod k + k, ... in one launch of k n threads (run here as a
// grid-stride loop over those virtual threads, since k is known only on the device).
// triangle_parallel_kernel is the baseline: one thread walks a whole box.
#include <algorithm>
#include <climits>
#include <cub/block/block_reduce.cuh>

#include "resolve.cuh"

namespace fluidweight::detail::gpu {
namespace {

constexpr int kBlock = 256;

// Steps 3-4 for the candidates cur, cur + k, ... (< box) of triangle t's box, starting at
// column (i, j); k = di + dj width. A hit goes to its column's next slot. The candidates are
// tested kBatch at a time and their hits' slot atomics issued together: one after the other,
// each hit waited for its slot's round trip (docs/fluidweight.md, "What was tried and dropped").
constexpr int kBatch = 4;

template <typename Index, typename Real>
__device__ inline void raster_candidates(const Batch<Real>& b, const DevTri<Real>& t, int tri,
                                         Index cur, Index box, Index k, int i, Index j, int di,
                                         Index dj) {
  const int sub_bits = b.cavities[cavity_of(t.flags)].grid.sub_bits;
  const size_t columns = static_cast<size_t>(b.num_cavities) * b.n * b.n;
  const size_t first = static_cast<size_t>(cavity_of(t.flags)) * b.n * b.n;
  const int width = t.i1 - t.i0 + 1;
  const int tag = is_floor(t.flags) ? ~tri : tri;
  while (cur < box) {
    size_t col[kBatch];
    Real z[kBatch];
    bool hit[kBatch];
#pragma unroll
    for (int q = 0; q < kBatch; ++q) {
      int64_t e[3];
      hit[q] =
          cur < box && covers_column(t, column_centre(i, sub_bits), column_centre(j, sub_bits), e);
      col[q] = first + static_cast<size_t>(j) * b.n + i;
      z[q] = hit[q] ? height_at(t, e) : Real(0);
      cur += k;
      i += di;
      j += dj;
      if (i > t.i1) {
        i -= width;
        ++j;
      }
    }
    int slot[kBatch];
#pragma unroll
    for (int q = 0; q < kBatch; ++q) slot[q] = hit[q] ? atomicAdd(&b.column_count[col[q]], 1) : 0;
#pragma unroll
    for (int q = 0; q < kBatch; ++q) {
      if (hit[q] && slot[q] < b.column_capacity) {
        b.column_z[slot[q] * columns + col[q]] = z[q];
        b.column_tag[slot[q] * columns + col[q]] = tag;
      }
    }
  }
}

// The virtual threads of Algorithm 1 by a grid stride. Index is int when the launch's k n
// threads and every box fit it (the usual case: 64-bit divisions cost ~70 instructions,
// 32-bit ones ~20); a thread steps from candidate to candidate by additions.
template <typename Index, typename Real>
__device__ inline void leveraging_threads(const Batch<Real>& b, Index k, Index threads) {
  const Index stride = static_cast<Index>(gridDim.x) * blockDim.x;
  for (Index id = static_cast<Index>(blockIdx.x) * blockDim.x + threadIdx.x; id < threads;
       id += stride) {
    const Index tri = id / k;
    const DevTri<Real> t = load_tri(&b.tris[tri]);
    const int width = t.i1 - t.i0 + 1, height = t.j1 - t.j0 + 1;
    if (width <= 0 || height <= 0) continue;
    const Index box = static_cast<Index>(width) * height;
    const Index cur = id - tri * k;  // this thread's first candidate: id mod k
    if (cur >= box) continue;
    raster_candidates(b, t, static_cast<int>(tri), cur, box, k,
                      t.i0 + static_cast<int>(cur % width), t.j0 + cur / width,
                      static_cast<int>(k % width), k / width);
  }
}

template <typename Real>
__global__ void __launch_bounds__(kBlock) leveraging_kernel(Batch<Real> b) {
  using Reduce = cub::BlockReduce<unsigned long long, kBlock>;
  __shared__ typename Reduce::TempStorage storage;
  __shared__ unsigned long long candidates;
  let_next_start();
  wait_previous();  // setup_kernel's triangles (launch_overlapped)
  unsigned long long sum = 0;
  for (int k = threadIdx.x; k < b.setup_blocks; k += blockDim.x) sum += b.candidates[k];
  sum = Reduce(storage).Sum(sum);
  if (threadIdx.x == 0) candidates = sum;
  __syncthreads();
  const double c = static_cast<double>(candidates) / b.num_triangles;
  const long long k = max(1ll, static_cast<long long>(floor(b.alpha * c)));
  const long long threads = k * b.num_triangles;
  // Boxes of at most 2^30 columns and k of at most 2^30: cur + k and id + stride stay in int.
  if (threads <= (1 << 30) && b.n <= (1 << 15)) {
    leveraging_threads<int>(b, static_cast<int>(k), static_cast<int>(threads));
  } else {
    leveraging_threads<long long>(b, k, threads);
  }
}

template <typename Real>
__global__ void __launch_bounds__(kBlock) triangle_parallel_kernel(Batch<Real> b) {
  let_next_start();
  wait_previous();  // setup_kernel's triangles (launch_overlapped)
  const int tri = blockIdx.x * blockDim.x + threadIdx.x;
  if (tri >= b.num_triangles) return;
  const DevTri<Real> t = load_tri(&b.tris[tri]);
  if (t.i0 > t.i1 || t.j0 > t.j1) return;
  const long long box = static_cast<long long>(t.i1 - t.i0 + 1) * (t.j1 - t.j0 + 1);
  raster_candidates(b, t, tri, 0ll, box, 1ll, t.i0, static_cast<long long>(t.j0), 1, 0ll);
}

// Step 5, one thread per column; resets the column's count for the next call. Block row y
// takes cavity y's columns (so a block's sums go to one cavity). The column's hits are first
// copied to shared memory, all their loads in flight together, and sorted there: sorted in
// place in global memory, each of the sort's dependent accesses was a round trip to L2 (the
// columns with most hits decided the kernel's time). One block per 128 columns, not a grid
// stride: the kernel is bound by instructions, not by its blocks' start and end.
template <typename Real, int Block>
__global__ void __launch_bounds__(Block) column_kernel(Batch<Real> b) {
  using Reduce = cub::BlockReduce<double, Block>;
  using ReduceCount = cub::BlockReduce<unsigned, Block>;
  __shared__ typename Reduce::TempStorage storage;
  __shared__ typename ReduceCount::TempStorage count_storage;
  extern __shared__ __align__(16) unsigned char staged[];  // column_capacity hits a thread
  wait_previous();  // the raster kernel's hits (launch_overlapped)
  Real* staged_z = reinterpret_cast<Real*>(staged);
  int* staged_tag = reinterpret_cast<int*>(staged_z + b.column_capacity * Block);
  const int cavity = blockIdx.y;
  const size_t per_cavity = static_cast<size_t>(b.n) * b.n;
  const size_t columns = per_cavity * b.num_cavities;
  const GridParams& grid = b.cavities[cavity].grid;
  ColumnHits<Real> hits{staged_z + threadIdx.x, staged_tag + threadIdx.x, Block};
  double sum_heights = 0.0;
  unsigned unmatched = 0;
  // The stride is a multiple of the block, so all 32 lanes of a warp make the same rounds
  // (resolve_column's warp operations need them).
  for (size_t base = static_cast<size_t>(blockIdx.x) * Block; base < per_cavity;
       base += static_cast<size_t>(gridDim.x) * Block) {
    const size_t local = base + threadIdx.x;
    const size_t col = cavity * per_cavity + local;
    int n = 0, i = 0, j = 0;
    if (local < per_cavity) {
      // 32-bit division (~20 instructions against ~70) whenever the grid allows it.
      if (per_cavity <= UINT_MAX) {
        j = static_cast<int>(static_cast<unsigned>(local) / static_cast<unsigned>(b.n));
        i = static_cast<int>(static_cast<unsigned>(local) - static_cast<unsigned>(j) * b.n);
      } else {
        j = static_cast<int>(local / b.n);
        i = static_cast<int>(local % b.n);
      }
      n = b.column_count[col];
      if (n) {
        b.column_count[col] = 0;
        if (n > b.column_capacity) {
          atomicMax(&b.status->max_column_hits, n);
          n = b.column_capacity;
        }
      }
    }
#pragma unroll 4
    for (int s = 0; s < n; ++s) {
      staged_z[s * Block + threadIdx.x] = b.column_z[s * columns + col];
      staged_tag[s * Block + threadIdx.x] = b.column_tag[s * columns + col];
    }
    resolve_column(b, hits, n, i, j, grid, sum_heights, unmatched, GlobalFloors<Real>{b});
  }
  const double s = Reduce(storage).Sum(sum_heights);
  const unsigned u = ReduceCount(count_storage).Sum(unmatched);
  if (threadIdx.x == 0) {
    const int stripe = blockIdx.x % kStripes;
    if (s != 0.0) atomicAdd(&b.cavities[cavity].sum_heights[stripe], s);
    if (u) atomicAdd(&b.cavities[cavity].unmatched[stripe], static_cast<unsigned long long>(u));
  }
}

template <typename Real, int Block>
void launch_column_kernel(const Batch<Real>& b, size_t shared, cudaStream_t stream) {
  cudaFuncSetAttribute(column_kernel<Real, Block>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                       static_cast<int>(shared));
  const size_t per_cavity = static_cast<size_t>(b.n) * b.n;
  const dim3 blocks(static_cast<unsigned>((per_cavity + Block - 1) / Block), b.num_cavities);
  launch_overlapped(b.overlap >= 2, column_kernel<Real, Block>, blocks, Block, shared, stream, b);
}

}  // namespace

template <typename Real>
void launch_raster(const Batch<Real>& b, bool leveraging, int num_sms, cudaStream_t stream) {
  if (leveraging) {
    launch_overlapped(b.overlap >= 2, leveraging_kernel<Real>, num_sms * 8, kBlock, 0, stream, b);
  } else {
    int blocks = (b.num_triangles + kBlock - 1) / kBlock;
    launch_overlapped(b.overlap >= 2, triangle_parallel_kernel<Real>, blocks, kBlock, 0, stream, b);
  }
}

template <typename Real>
size_t column_shared_bytes(int column_capacity, int block) {
  return static_cast<size_t>(column_capacity) * block * (sizeof(Real) + sizeof(int));
}

// Blocks of 128 columns, or of 32 when a column's hits are too many for 128 in shared memory.
template <typename Real>
void launch_columns(const Batch<Real>& b, int max_shared, cudaStream_t stream) {
  const size_t shared = column_shared_bytes<Real>(b.column_capacity, 128);
  if (shared <= static_cast<size_t>(max_shared) - 8 * 1024) {
    launch_column_kernel<Real, 128>(b, shared, stream);
  } else {
    launch_column_kernel<Real, 32>(b, column_shared_bytes<Real>(b.column_capacity, 32), stream);
  }
}

template void launch_raster<float>(const Batch<float>&, bool, int, cudaStream_t);
template void launch_raster<double>(const Batch<double>&, bool, int, cudaStream_t);
template void launch_columns<float>(const Batch<float>&, int, cudaStream_t);
template void launch_columns<double>(const Batch<double>&, int, cudaStream_t);
template size_t column_shared_bytes<float>(int, int);
template size_t column_shared_bytes<double>(int, int);

}  // namespace fluidweight::detail::gpu
