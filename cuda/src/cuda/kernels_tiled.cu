// Steps 3-5 by tiles of TILE x TILE columns, one block a tile, hits kept in shared memory.
//
// The setup kernel has listed, for each tile, the triangles whose box meets it (triangles over
// very many tiles sit in one list that every tile reads). A block takes its tile's triangles a
// round of TILE^2 at a time: each triangle's candidates are the columns of its box inside the
// tile; an exclusive scan of their counts lays all candidates of the round end to end, and the
// block's warps take them 32 at a time, one a lane (tile_raster.cuh). So a triangle covering
// the whole tile and one covering a single column cost the same per candidate, whatever the
// mix: the balance the leveraging kernel gets from its average c, here exact per tile. Hits go
// to per-column slots in shared memory; then each thread resolves one column (Step 5) and only
// the nodal weights leave the chip.
#include <algorithm>
#include <cub/block/block_scan.cuh>

#include "resolve.cuh"
#include "tile_raster.cuh"

namespace fluidweight::detail::gpu {
namespace {

// A round's triangles, staged in shared memory for the raster (tile_raster.cuh), with what
// Step 5 needs of the last round's floors: corner 0 (x in the raster stage's spare word of
// dy, y here; the other corners follow from the edge vectors) and the vertices.
template <typename Real, int N>
struct Staged {
  RasterStage<Real, N> r;
  int y0[N], vertex[3][N];
};

// Floors for Step 5: the last round's triangles from shared memory, earlier ones from global.
// The key that the warp's lanes match on is the item (unique in the tile) in both cases.
template <typename Real, int N>
struct TileFloors {
  const Batch<Real>& b;
  const Staged<Real, N>& s;
  const int* list;
  int listed, staged_first;
  __device__ FloorAtColumn operator()(int item, int px, int py) const {
    if (item < staged_first) {
      int tri = item < listed ? list[item] : b.big_list[item - listed];
      FloorAtColumn f = GlobalFloors<Real>{b}(tri, px, py);
      f.key = item;
      return f;
    }
    const int k = item - staged_first;
    FloorAtColumn f;
    f.key = item;
    for (int c = 0; c < 3; ++c) f.vertex[c] = s.vertex[c][k];
    const int4 dx = s.r.dx[k], dy = s.r.dy[k];
    // Corner 1 = corner 0 + edge 2's vector, corner 2 = corner 1 + edge 0's.
    const int x0 = dy.w, y0 = s.y0[k];
    const int x1 = x0 + dx.z, y1 = y0 + dy.z, x2 = x1 + dx.x, y2 = y1 + dy.x;
    f.e[0] = edge_function(x1, y1, x2, y2, px, py);
    f.e[1] = edge_function(x2, y2, x0, y0, px, py);
    f.e[2] = edge_function(x0, y0, x1, y1, px, py);
    return f;
  }
};

// One tile: Steps 3-5 of its columns. `listed` and `first_entry` (this thread's first list
// entry, read before the count was known: the list has room for at least kThreads entries and
// an entry past the count is not used) were loaded by the caller, ahead of time.
// ROUND: triangles staged at a time (TILE^2, or half of it for less shared memory: more
// blocks an SM where the hit slots are many).
template <typename Real, int TILE, int ROUND>
__device__ __forceinline__ void tile_columns(const Batch<Real>& b, int tile, int listed,
                                             int first_entry) {
  constexpr int kThreads = TILE * TILE;  // also the columns of a tile
  using Scan = cub::BlockScan<int, kThreads>;
  __shared__ typename Scan::TempStorage scan_storage;
  __shared__ double warp_sum[kThreads / 32];
  __shared__ unsigned warp_unmatched[kThreads / 32];
  __shared__ Staged<Real, ROUND> s;
  extern __shared__ __align__(16) unsigned char dynamic[];
  const int capacity = b.column_capacity;
  // Threads that stage a triangle (all of them with a whole round: no test compiled in).
  const bool stager = ROUND == kThreads || static_cast<int>(threadIdx.x) < ROUND;
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
  for (;; first += ROUND) {
    // This round's triangles and their candidate rectangles inside the tile.
    const int e = first + threadIdx.x;
    int tri = 0, count = 0, ci = 0, cj = 0, width = 0;
    DevTri<Real> t{};
    if (stager && e < items) {
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
    Scan(scan_storage).ExclusiveSum(count, offset, total);
    const int k = threadIdx.x;
    if (stager) {
      const Real z[3] = {t.z[0], t.z[1], t.z[2]};
      stage_entry<Real, TILE>(s.r, k, t.x, t.y, z, t.flags, first + k, ci, cj,
                              count > 0 ? width : 0, ti0, tj0, sub_bits, t.x[0]);
      s.y0[k] = t.y[0];
      for (int c = 0; c < 3; ++c) s.vertex[c][k] = t.vertex[c];
      s.r.offset[k] = offset;
    }
    if (k == 0) s.r.offset[ROUND] = total;
    __syncthreads();

    // Steps 3-4: the round's candidates dealt out to the warps, 32 at a time.
    raster_round<Real, TILE>(s.r, ROUND, total, s_z, s_tag, s_count, capacity);
    if (first + ROUND >= items) break;
  }
  __syncthreads();

  // Step 5, one column per thread.
  int n = s_count[threadIdx.x];
  if (n > capacity) {
    atomicMax(&b.status->max_column_hits, n);
    n = capacity;
  }
  const int i = ti0 + threadIdx.x % TILE, j = tj0 + threadIdx.x / TILE;
  double sum_heights = 0.0;
  unsigned unmatched = 0;
  resolve_column(b, ColumnHits<Real>{s_z + threadIdx.x, s_tag + threadIdx.x, kThreads}, n, i, j,
                 grid, sum_heights, unmatched, TileFloors<Real, ROUND>{b, s, list, listed, first});
  // The block's sums: warp shuffles, then one barrier (cub's two block reductions took two
  // more and their own).
  for (int d = 16; d > 0; d >>= 1) {
    sum_heights += __shfl_xor_sync(kFullMask, sum_heights, d);
    unmatched += __shfl_xor_sync(kFullMask, unmatched, d);
  }
  if ((threadIdx.x & 31) == 0) {
    warp_sum[threadIdx.x / 32] = sum_heights;
    warp_unmatched[threadIdx.x / 32] = unmatched;
  }
  __syncthreads();
  if (threadIdx.x == 0) {
    double sum = 0.0;
    unsigned u = 0;
    for (int w = 0; w < kThreads / 32; ++w) {
      sum += warp_sum[w];
      u += warp_unmatched[w];
    }
    const int stripe = tile % kStripes;
    if (sum != 0.0) atomicAdd(&b.cavities[cavity].sum_heights[stripe], sum);
    if (u) atomicAdd(&b.cavities[cavity].unmatched[stripe], static_cast<unsigned long long>(u));
  }
}

// Tiles empty at the previous call (the last positions of the order) are checked this many to a
// block (Batch::group_empty): a block of an empty tile costs its launch and two dependent loads
// (order, count) while it holds one of the SM's few block slots, and over half of the
// armadillo's tiles at 1000^2-1500^2 are empty: several waves of such blocks.
constexpr int kEmptyGroup = 8;

// Block k takes the tile at position k of the tile order (order_kernel's, or the grid's when
// there is none). With Batch::group_empty (an order), block first_empty + g (first_empty: the
// previous call's first empty position, order[tiles]) checks positions first_empty +
// kEmptyGroup g and the next ones together and, should any of them not be empty now (the cavity
// moved), takes them one after another from the first such to the last; the blocks left without
// positions exit after one load. The next tile's count and first list entries are loaded before
// this one is worked on, so an empty tile costs no round trip and a full one starts with its
// triangles' loads.
template <typename Real, int TILE, int ROUND>
__global__ void __launch_bounds__(TILE* TILE, 2048 / (TILE * TILE * 2)) tile_kernel(Batch<Real> b) {
  const int tiles = b.num_cavities * b.tiles_per_side * b.tiles_per_side;
  int index = blockIdx.x;
  if (index >= tiles) return;
  auto tile_at = [&](int k) { return b.tile_order ? b.tile_order[k] : k; };
  auto entry = [&](int t) {
    return b.tile_list[static_cast<size_t>(t) * b.tile_capacity + threadIdx.x];
  };
  // Both written by an earlier call, so loaded before the wait and together.
  int tile = tile_at(index);
  const int first_empty = b.group_empty && b.tile_order ? b.tile_order[tiles] : tiles;
  int step = tiles, end = tiles;  // one tile a block, unless it checks a group of empty ones
  if (index >= first_empty) {
    const int first = first_empty + (index - first_empty) * kEmptyGroup;
    if (first >= tiles) return;
    const int lane = threadIdx.x & 31;
    const int t = lane < kEmptyGroup && first + lane < tiles ? b.tile_order[first + lane] : -1;
    wait_previous();  // setup_kernel's lists
    const int big = *b.big_count, n = t >= 0 ? b.tile_count[count_slot(t)] : 0;
    const unsigned work = __ballot_sync(kFullMask, t >= 0 && (n > 0 || big > 0));
    if (!work) return;
    index = first + __ffs(work) - 1;
    tile = __shfl_sync(kFullMask, t, __ffs(work) - 1);
    step = 1;
    end = first + 32 - __clz(work);
  } else {
    wait_previous();  // setup_kernel's lists
  }
  int listed = b.tile_count[count_slot(tile)], first_entry = entry(tile);
  while (true) {
    const int next_index = index + step;
    int next = -1, next_listed = 0, next_entry = 0;
    if (next_index < end) {
      next = tile_at(next_index);
      next_listed = b.tile_count[count_slot(next)];
      next_entry = entry(next);
    }
    tile_columns<Real, TILE, ROUND>(b, tile, listed, first_entry);
    if (next < 0) break;
    __syncthreads();  // shared memory is reused by the next tile
    index = next_index;
    tile = next;
    listed = next_listed;
    first_entry = next_entry;
  }
}

// The tiles by decreasing number of listed triangles into `order` (the host makes this call's
// order the next call's, see ordered() in device_tiled.cu): the hardware starts blocks in grid
// order, so the longest tiles start in the first wave instead of ending the kernel alone on a
// few SMs (longest first). Eight classes by powers of two suffice (a scheduling model put
// them close to a full sort by candidates); empty tiles
// come last. One small block, so that it finds room beside the tile kernel's blocks early (a
// block of 1024 threads waited for an SM to empty, at the tile kernel's end); at most
// kMaxOrderedTiles tiles (the host checks). Classes are counted by warp ballots, one a class.
constexpr int kOrderThreads = 256, kOrderClasses = 8, kMaxOrderedTiles = 16384;

__device__ __forceinline__ int order_class(int count) {
  if (count <= 0) return kOrderClasses - 1;
  const int log2 = 31 - __clz(count);  // 256 or more: class 0, ..., 1-7: class 6
  return min(kOrderClasses - 2, max(0, 8 - log2));
}

__global__ void __launch_bounds__(kOrderThreads)
    order_kernel(const int* count, const int* big_count, int tiles, int* order) {
  __shared__ unsigned char cls[kMaxOrderedTiles];
  __shared__ int total[kOrderClasses], first[kOrderClasses];
  const int lane = threadIdx.x & 31;
  if (threadIdx.x < kOrderClasses) total[threadIdx.x] = 0;
  // Classes, four loads a thread in flight, and the warp's tiles of each (lane c counts c).
  int mine = 0;
  for (int base = 0; base < tiles; base += 4 * kOrderThreads) {
    int k[4];
#pragma unroll
    for (int q = 0; q < 4; ++q) {
      const int t = base + q * kOrderThreads + threadIdx.x;
      k[q] = t < tiles ? order_class(__ldg(&count[count_slot(t)])) : -1;
    }
#pragma unroll
    for (int q = 0; q < 4; ++q) {
      const int t = base + q * kOrderThreads + threadIdx.x;
      if (k[q] >= 0) cls[t] = static_cast<unsigned char>(k[q]);
#pragma unroll
      for (int c = 0; c < kOrderClasses; ++c) {
        const int n = __popc(__ballot_sync(kFullMask, k[q] == c));
        if (lane == c) mine += n;
      }
    }
  }
  __syncthreads();
  int run = lane < kOrderClasses ? atomicAdd(&total[lane], mine) : 0;  // the warp's place
  __syncthreads();
  if (threadIdx.x == 0) {
    int sum = 0;
    for (int c = 0; c < kOrderClasses; ++c) {
      first[c] = sum;
      sum += total[c];
    }
    // The empty tiles' first position (tile_kernel), or none where triangles over many tiles
    // give every tile work: a block would then take its group's eight tiles one after another.
    order[tiles] = *big_count > 0 ? tiles : first[kOrderClasses - 1];
  }
  __syncthreads();
  if (lane < kOrderClasses) run += first[lane];
  const unsigned below = (1u << lane) - 1;
  for (int t = threadIdx.x; t < (tiles + 31) / 32 * 32; t += kOrderThreads) {
    const int k = t < tiles ? cls[t] : -1;
#pragma unroll
    for (int c = 0; c < kOrderClasses; ++c) {
      const unsigned m = __ballot_sync(kFullMask, k == c);
      const int at = __shfl_sync(kFullMask, run, c);
      if (k == c) order[at + __popc(m & below)] = t;
      if (lane == c) run += __popc(m);
    }
  }
}

}  // namespace

template <typename Real>
size_t tile_shared_bytes(int tile_bits, int column_capacity) {
  size_t columns = size_t{1} << (2 * tile_bits);
  return column_capacity * columns * (sizeof(Real) + sizeof(int)) + columns * sizeof(int);
}

// f(kernel, threads) with the tile kernel of that tile and round.
template <typename Real, typename F>
void with_tile_kernel(int tile_bits, bool half_round, F&& f) {
  if (tile_bits == 3) {
    if (half_round) {
      f(tile_kernel<Real, 8, 32>, 64);
    } else {
      f(tile_kernel<Real, 8, 64>, 64);
    }
  } else if (half_round) {
    f(tile_kernel<Real, 16, 128>, 256);
  } else {
    f(tile_kernel<Real, 16, 256>, 256);
  }
}

template <typename Real>
void allow_tile_shared(size_t bytes) {
  for (int bits : {3, 4}) {
    for (bool half : {false, true}) {
      with_tile_kernel<Real>(bits, half, [&](auto kernel, int) {
        cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize,
                             static_cast<int>(bytes));
      });
    }
  }
}

// One block a tile: a persistent grid (a block taking tiles by stride or by claims from a
// counter) balanced the heaviest tiles worse than the hardware's block scheduler.
template <typename Real>
void launch_tiles(const Batch<Real>& b, cudaStream_t stream) {
  const int tiles = b.num_cavities * b.tiles_per_side * b.tiles_per_side;
  const size_t shared = tile_shared_bytes<Real>(b.tile_bits, b.column_capacity);
  with_tile_kernel<Real>(b.tile_bits, b.half_round, [&](auto kernel, int threads) {
    launch_overlapped(b.overlap >= 2, kernel, tiles, threads, shared, stream, b);
  });
}

template <typename Real>
int tile_resident_blocks(int tile_bits, bool half_round, size_t shared) {
  int fit = 0;
  with_tile_kernel<Real>(tile_bits, half_round, [&](auto kernel, int threads) {
    cudaOccupancyMaxActiveBlocksPerMultiprocessor(&fit, kernel, threads, shared);
  });
  return fit;
}

int max_ordered_tiles() { return kMaxOrderedTiles; }

void launch_tile_order(const int* count, const int* big_count, int tiles, int* order,
                       cudaStream_t stream) {
  order_kernel<<<1, kOrderThreads, 0, stream>>>(count, big_count, tiles, order);
}

template size_t tile_shared_bytes<float>(int, int);
template size_t tile_shared_bytes<double>(int, int);
template void allow_tile_shared<float>(size_t);
template void allow_tile_shared<double>(size_t);
template void launch_tiles<float>(const Batch<float>&, cudaStream_t);
template void launch_tiles<double>(const Batch<double>&, cudaStream_t);
template int tile_resident_blocks<float>(int, bool, size_t);
template int tile_resident_blocks<double>(int, bool, size_t);

}  // namespace fluidweight::detail::gpu
