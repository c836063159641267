// Steps 3-5 by tiles of TILE x TILE columns, one block a tile, hits kept in shared memory.
//
// The setup kernel has listed, for each tile, the triangles whose box meets it (triangles over
// very many tiles sit in one list that every tile reads). A block takes its tile's triangles a
// round of TILE^2 at a time: each triangle's candidates are the columns of its box inside the
// tile; an exclusive scan of their counts lays all candidates of the round end to end, and each
// thread tests an equal, contiguous share of them, finding its first triangle by binary search
// (a load-balanced search). So a triangle covering the whole tile and one covering a single
// column cost the same per candidate, whatever the mix: the balance the leveraging kernel gets
// from its average c, here exact per tile. Hits go to per-column slots in shared memory; then
// each thread resolves one column (Step 5) and only the nodal weights leave the chip.
#include <algorithm>

#include <cub/block/block_reduce.cuh>
#include <cub/block/block_scan.cuh>

#include "resolve.cuh"

namespace fluidweight::detail::gpu {
namespace {

// A round's triangles, staged in shared memory (structure of arrays: no bank conflicts). The
// height plane is set up once per triangle when it is staged: z0 at the first candidate
// (ci, cj) of its rectangle in the tile, dzi and dzj its steps along a row and a column.
template <typename Real, int N>
struct Staged {
  int x[3][N], y[3][N], vertex[3][N];
  int flags[N], tri[N], ci[N], cj[N], width[N], offset[N + 1];
  Real z0[N], dzi[N], dzj[N];
};

// Floors for Step 5: the last round's triangles from shared memory, earlier ones from global.
template <typename Real, int N>
struct TileFloors {
  const Batch<Real>& b;
  const Staged<Real, N>& s;
  const int* list;
  int listed, staged_first;
  __device__ FloorAtColumn operator()(int item, int px, int py) const {
    if (item < staged_first) {
      int tri = item < listed ? list[item] : b.big_list[item - listed];
      return GlobalFloors<Real>{b}(tri, px, py);
    }
    const int k = item - staged_first;
    FloorAtColumn f;
    f.key = s.tri[k];
    for (int c = 0; c < 3; ++c) f.vertex[c] = s.vertex[c][k];
    f.e[0] = edge_function(s.x[1][k], s.y[1][k], s.x[2][k], s.y[2][k], px, py);
    f.e[1] = edge_function(s.x[2][k], s.y[2][k], s.x[0][k], s.y[0][k], px, py);
    f.e[2] = edge_function(s.x[0][k], s.y[0][k], s.x[1][k], s.y[1][k], px, py);
    return f;
  }
};

// One tile: Steps 3-5 of its columns. `listed` and `first_entry` (this thread's first list
// entry, read before the count was known: the list has room for at least kThreads entries and
// an entry past the count is not used) were loaded by the caller, ahead of time.
template <typename Real, int TILE>
__device__ __forceinline__ void tile_columns(const Batch<Real>& b, int tile, int listed,
                                             int first_entry) {
  constexpr int kThreads = TILE * TILE;  // also the columns of a tile
  using Scan = cub::BlockScan<int, kThreads>;
  using Reduce = cub::BlockReduce<double, kThreads>;
  using ReduceCount = cub::BlockReduce<unsigned, kThreads>;
  __shared__ union {
    typename Scan::TempStorage scan;
    typename Reduce::TempStorage reduce;
    typename ReduceCount::TempStorage count;
  } storage;
  __shared__ Staged<Real, kThreads> s;
  extern __shared__ __align__(16) unsigned char dynamic[];
  const int capacity = b.column_capacity;
  Real* s_z = reinterpret_cast<Real*>(dynamic);  // slot * kThreads + column
  int* s_tag = reinterpret_cast<int*>(s_z + capacity * kThreads);
  int* s_count = s_tag + capacity * kThreads;

  const int tiles_per_cavity = b.tiles_per_side * b.tiles_per_side;
  const int cavity = tile / tiles_per_cavity;
  const int local_tile = tile % tiles_per_cavity;
  const int ti0 = (local_tile % b.tiles_per_side) * TILE;
  const int tj0 = (local_tile / b.tiles_per_side) * TILE;
  const int* list = b.tile_list + static_cast<size_t>(tile) * b.tile_capacity;
  if (listed > b.tile_capacity) {
    if (threadIdx.x == 0) atomicMax(&b.status->max_tile_count, listed);
    return;
  }
  const int items = listed + *b.big_count;
  if (items == 0) return;
  const GridParams grid = b.cavities[cavity].grid;
  const int sub_bits = grid.sub_bits;
  s_count[threadIdx.x] = 0;

  int first = 0;
  for (;; first += kThreads) {
    // This round's triangles and their candidate rectangles inside the tile.
    const int e = first + threadIdx.x;
    int tri = 0, count = 0, ci = 0, cj = 0, width = 0;
    DevTri<Real> t{};
    if (e < items) {
      tri = e < listed ? (first == 0 ? first_entry : list[e]) : b.big_list[e - listed];
      t = load_tri(&b.tris[tri]);
      if (cavity_of(t.flags) == cavity) {
        ci = max(t.i0, ti0);
        cj = max(t.j0, tj0);
        width = min(t.i1, ti0 + TILE - 1) - ci + 1;
        int height = min(t.j1, tj0 + TILE - 1) - cj + 1;
        if (width > 0 && height > 0) count = width * height;
      }
    }
    __syncthreads();  // the previous round is done with the staged triangles
    int offset, total;
    Scan(storage.scan).ExclusiveSum(count, offset, total);
    const int k = threadIdx.x;
    {
      // The height plane at the first candidate and its steps, once per triangle, so that a
      // thread entering the triangle needs no division.
      const int px = column_centre(ci, sub_bits), py = column_centre(cj, sub_bits);
      Real area = 0, z0 = 0, zi = 0, zj = 0;
      if (count > 0) {
        for (int c = 0; c < 3; ++c) {
          const int p = (c + 1) % 3, q = (c + 2) % 3;
          const int64_t ec = edge_function(t.x[p], t.y[p], t.x[q], t.y[q], px, py);
          const int64_t di = -static_cast<int64_t>(t.y[q] - t.y[p]) << sub_bits;
          const int64_t dj = static_cast<int64_t>(t.x[q] - t.x[p]) << sub_bits;
          area += static_cast<Real>(ec);
          z0 += static_cast<Real>(ec) * t.z[c];
          zi += static_cast<Real>(di) * t.z[c];
          zj += static_cast<Real>(dj) * t.z[c];
        }
        const Real inv = Real(1) / area;
        z0 *= inv;
        zi *= inv;
        zj *= inv;
      }
      s.z0[k] = z0;
      s.dzi[k] = zi;
      s.dzj[k] = zj;
    }
    for (int c = 0; c < 3; ++c) {
      s.x[c][k] = t.x[c];
      s.y[c][k] = t.y[c];
      s.vertex[c][k] = t.vertex[c];
    }
    s.flags[k] = t.flags;
    s.tri[k] = tri;
    s.ci[k] = ci;
    s.cj[k] = cj;
    s.width[k] = width;
    s.offset[k] = offset;
    if (k == 0) s.offset[kThreads] = total;
    __syncthreads();

    // Steps 3-4: an equal, contiguous share of the candidates per thread.
    const int share = (b.diagnostic_phases & 1) ? (total + kThreads - 1) / kThreads : 0;
    int f = threadIdx.x * share;
    const int end = min(f + share, total);
    if (f < end) {
      int lo = 0, hi = kThreads - 1;  // the last triangle whose candidates start at or before f
      while (lo < hi) {
        int mid = (lo + hi + 1) >> 1;
        if (s.offset[mid] <= f) {
          lo = mid;
        } else {
          hi = mid - 1;
        }
      }
      // Walk the share; on each new triangle, its edge functions and height at the first
      // candidate and their steps along a row and at a row's end (exact integer steps).
      int item = lo - 1, next = s.offset[lo], li = 0, w = 1, col = 0, tag = 0;
      int64_t e[3], step[3], wrap[3], e_min[3];
      Real z = 0, dz = 0, dz_wrap = 0;
      for (; f < end; ++f) {
        if (f >= next) {
          do {
            ++item;
            next = s.offset[item + 1];
          } while (f >= next);
          // Entering a triangle: its edge functions at this candidate and their steps; the
          // height from the plane staged with it (no division, no 64-bit conversions).
          w = s.width[item];
          const int q0 = f - s.offset[item];
          // q0 < TILE^2 and w <= TILE: the float quotient is exact after truncation.
          const int lj = __float2int_rz(__fdividef(static_cast<float>(q0) + 0.5f, static_cast<float>(w)));
          li = q0 - lj * w;
          const int i = s.ci[item] + li, j = s.cj[item] + lj;
          const int px = column_centre(i, sub_bits), py = column_centre(j, sub_bits);
          const int flags = s.flags[item];
          for (int c = 0; c < 3; ++c) {
            const int p = (c + 1) % 3, q = (c + 2) % 3;
            const int xp = s.x[p][item], yp = s.y[p][item];
            const int xq = s.x[q][item], yq = s.y[q][item];
            e[c] = edge_function(xp, yp, xq, yq, px, py);
            step[c] = -static_cast<int64_t>(yq - yp) << sub_bits;
            wrap[c] = (static_cast<int64_t>(xq - xp) << sub_bits) - step[c] * (w - 1);
            e_min[c] = (flags >> c) & 1;
          }
          dz = s.dzi[item];
          const Real dzj = s.dzj[item];
          z = s.z0[item] + dz * static_cast<Real>(li) + dzj * static_cast<Real>(lj);
          dz_wrap = dzj - dz * static_cast<Real>(w - 1);
          col = (j - tj0) * TILE + (i - ti0);
          tag = is_floor(flags) ? ~(first + item) : first + item;
        }
        if (e[0] >= e_min[0] && e[1] >= e_min[1] && e[2] >= e_min[2]) {
          const int slot = atomicAdd(&s_count[col], 1);
          if (slot < capacity) {
            s_z[slot * kThreads + col] = z;
            s_tag[slot * kThreads + col] = tag;
          }
        }
        if (++li == w) {
          li = 0;
          col += TILE - (w - 1);
          z += dz_wrap;
          for (int c = 0; c < 3; ++c) e[c] += wrap[c];
        } else {
          col += 1;
          z += dz;
          for (int c = 0; c < 3; ++c) e[c] += step[c];
        }
      }
    }
    if (first + kThreads >= items) break;
  }
  __syncthreads();

  // Step 5, one column per thread.
  int n = (b.diagnostic_phases & 2) ? s_count[threadIdx.x] : 0;
  if (n > capacity) {
    atomicMax(&b.status->max_column_hits, n);
    n = capacity;
  }
  const int i = ti0 + threadIdx.x % TILE, j = tj0 + threadIdx.x / TILE;
  double sum_heights = 0.0;
  unsigned unmatched = 0;
  resolve_column(b, ColumnHits<Real>{s_z + threadIdx.x, s_tag + threadIdx.x, kThreads}, n, i, j,
                 grid, sum_heights, unmatched,
                 TileFloors<Real, kThreads>{b, s, list, listed, first});
  __syncthreads();
  double sum = Reduce(storage.reduce).Sum(sum_heights);
  __syncthreads();
  unsigned u = ReduceCount(storage.count).Sum(unmatched);
  if (threadIdx.x == 0) {
    const int stripe = tile % kStripes;
    if (sum != 0.0) atomicAdd(&b.cavities[cavity].sum_heights[stripe], sum);
    if (u) atomicAdd(&b.cavities[cavity].unmatched[stripe], static_cast<unsigned long long>(u));
  }
}

// A block takes tiles blockIdx.x, blockIdx.x + gridDim.x, ... (one tile when the grid has a
// block per tile; a persistent grid of the blocks the GPU holds at once otherwise). The next
// tile's count and first list entries are loaded before this one is worked on, so an empty
// tile costs no round trip and a full one starts with its triangles' loads.
template <typename Real, int TILE>
__global__ void __launch_bounds__(TILE* TILE, 2048 / (TILE * TILE * 2)) tile_kernel(Batch<Real> b) {
  const int tiles = b.num_cavities * b.tiles_per_side * b.tiles_per_side;
  int tile = blockIdx.x;
  if (tile >= tiles) return;
  auto entry = [&](int t) { return b.tile_list[static_cast<size_t>(t) * b.tile_capacity + threadIdx.x]; };
  int listed = b.tile_count[tile], first_entry = entry(tile);
  while (true) {
    const int next = tile + gridDim.x;
    int next_listed = 0, next_entry = 0;
    if (next < tiles) {
      next_listed = b.tile_count[next];
      next_entry = entry(next);
    }
    tile_columns<Real, TILE>(b, tile, listed, first_entry);
    if (next >= tiles) break;
    __syncthreads();  // shared memory is reused by the next tile
    tile = next;
    listed = next_listed;
    first_entry = next_entry;
  }
}

}  // namespace

template <typename Real>
size_t tile_shared_bytes(int tile_bits, int column_capacity) {
  size_t columns = size_t{1} << (2 * tile_bits);
  return column_capacity * columns * (sizeof(Real) + sizeof(int)) + columns * sizeof(int);
}

template <typename Real>
void allow_tile_shared(size_t bytes) {
  cudaFuncSetAttribute(tile_kernel<Real, 8>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                       static_cast<int>(bytes));
  cudaFuncSetAttribute(tile_kernel<Real, 16>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                       static_cast<int>(bytes));
}

// blocks_per_sm > 0: a persistent grid of that many blocks per multiprocessor (at most the
// occupancy allows); 0: one block per tile.
template <typename Real>
void launch_tiles(const Batch<Real>& b, int num_sms, int blocks_per_sm, cudaStream_t stream) {
  int tiles = b.num_cavities * b.tiles_per_side * b.tiles_per_side;
  size_t shared = tile_shared_bytes<Real>(b.tile_bits, b.column_capacity);
  auto grid = [&](auto kernel, int threads) {
    if (blocks_per_sm <= 0) return tiles;
    int fit = 0;
    cudaOccupancyMaxActiveBlocksPerMultiprocessor(&fit, kernel, threads, shared);
    return std::max(1, std::min(tiles, num_sms * std::min(std::max(fit, 1), blocks_per_sm)));
  };
  if (b.tile_bits == 3) {
    tile_kernel<Real, 8><<<grid(tile_kernel<Real, 8>, 64), 64, shared, stream>>>(b);
  } else {
    tile_kernel<Real, 16><<<grid(tile_kernel<Real, 16>, 256), 256, shared, stream>>>(b);
  }
}

template size_t tile_shared_bytes<float>(int, int);
template size_t tile_shared_bytes<double>(int, int);
template void allow_tile_shared<float>(size_t);
template void allow_tile_shared<double>(size_t);
template void launch_tiles<float>(const Batch<float>&, int, int, cudaStream_t);
template void launch_tiles<double>(const Batch<double>&, int, int, cudaStream_t);

}  // namespace fluidweight::detail::gpu
