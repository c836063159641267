// Steps 1-5 in one launch, for cavities small enough that a few blocks can look at all their
// triangles (docs/fluidweight.md, "The fused kernel").
//
// A block owns a tile of TILE x TILE columns of one cavity (blockIdx.x and .y the tile,
// blockIdx.z the cavity); the blocks of a thread-block cluster (a row of up to 16 tiles) share
// the work that does not depend on the tile through their distributed shared memory:
//   1. each block reduces the projected box of a slice of the cavity's vertices; every block
//      reads the cluster's partial boxes and makes the same grid (min and max are exact, so
//      every cluster, and every block, finds the same grid);
//   2. each block snaps its slice of the vertices (the snap of geometry.hpp, per vertex rather
//      than per corner: the same numbers) into its shared memory;
//   3. each block sets up a slice of the cavity's triangles (setup_triangle, as every kernel
//      does), reading their corners from the blocks that snapped them, and appends each to the
//      item list of every tile of the cluster that its box meets;
//   4. each block rasterizes its items by rounds (tile_raster.cuh) and resolves its columns
//      (Step 5, resolve.cuh) in shared memory; only nodal weights leave the chip, by atomics.
// Every cluster repeats 1-3 for the whole cavity, so that no cluster waits for another.
//
// Two things the other kernels take from a first kernel are found otherwise:
// - Step 2's orientation (the sign of the signed volume) is assumed per cavity (+1 at first,
//   then the sign of the previous call) while the signed volume is summed by all blocks, each
//   a slice of the triangles; the host compares and runs the call again in the rare case the
//   sign changed (as it does when a buffer overflows).
// - The accumulators (nodal weights, volume sums, status) alternate between two sets: each
//   call clears the set of the next one.
#include <cooperative_groups.h>

#include <cub/block/block_scan.cuh>

#include "resolve.cuh"
#include "tile_raster.cuh"

namespace fluidweight::detail::gpu {
namespace {

namespace cg = cooperative_groups;

constexpr unsigned long long kCornerMask = (1ull << 21) - 1;
constexpr int kMaxCluster = 16;

__device__ __forceinline__ void unpack_corners(unsigned long long packed, int (&c)[3]) {
  c[0] = static_cast<int>(packed & kCornerMask);
  c[1] = static_cast<int>((packed >> 21) & kCornerMask);
  c[2] = static_cast<int>(packed >> 42);
}

// A triangle kept by a tile after Step 2: counter-clockwise snapped corners, their vertices
// (in the cavity) and heights, the fill rule's thresholds and floor bit (DevTri's flags).
template <typename Real>
struct alignas(16) Item {
  int x[3], y[3], vertex[3], flags;
  Real z[3];
};
template <typename Real>
constexpr int kItemWords = sizeof(Item<Real>) / 16;

// Offsets in the dynamic shared memory: the raster stage, the items, the block's slice of the
// vertex table (snapped x, y; height), the hits per column (slot-major) and their counts.
struct FusedLayout {
  size_t items, xy, z, hit_z, hit_tag, hit_count, total;
};

__host__ __device__ inline size_t align16(size_t x) { return (x + 15) / 16 * 16; }

template <typename Real>
__host__ __device__ inline FusedLayout fused_layout(size_t stage_bytes, int threads,
                                                    int slice_vertices, int capacity,
                                                    int item_capacity) {
  FusedLayout l;
  l.items = align16(stage_bytes);
  l.xy = align16(l.items + sizeof(Item<Real>) * item_capacity);
  l.z = align16(l.xy + sizeof(int2) * slice_vertices);
  l.hit_z = align16(l.z + sizeof(Real) * slice_vertices);
  l.hit_tag = align16(l.hit_z + sizeof(Real) * capacity * threads);
  l.hit_count = align16(l.hit_tag + sizeof(int) * capacity * threads);
  l.total = align16(l.hit_count + sizeof(int) * threads);
  return l;
}

// Floors for Step 5, from the tile's items.
template <typename Real>
struct ItemFloors {
  const Item<Real>* items;
  int first_vertex;
  __device__ FloorAtColumn operator()(int item, int px, int py) const {
    const Item<Real>& t = items[item];
    FloorAtColumn f;
    f.key = item;
    for (int k = 0; k < 3; ++k) f.vertex[k] = first_vertex + t.vertex[k];
    f.e[0] = edge_function(t.x[1], t.y[1], t.x[2], t.y[2], px, py);
    f.e[1] = edge_function(t.x[2], t.y[2], t.x[0], t.y[0], px, py);
    f.e[2] = edge_function(t.x[0], t.y[0], t.x[1], t.y[1], px, py);
    return f;
  }
};

// Blocks an SM should hold (registers; shared memory allows about three of 256 threads).
constexpr int min_blocks(int tile) { return tile == 16 ? 3 : 12; }

template <typename Real, int TILE>
__global__ void __launch_bounds__(TILE* TILE, min_blocks(TILE))
    fused_kernel(Batch<Real> b, FusedArgs<Real> f) {
  constexpr int kThreads = TILE * TILE;
  constexpr int kWarps = kThreads / 32;
  constexpr int kTileBits = TILE == 16 ? 4 : 3;
  using Scan = cub::BlockScan<int, kThreads>;
  __shared__ typename Scan::TempStorage scan_storage;
  __shared__ double box_scratch[kWarps][6];
  __shared__ double part_box[6];
  __shared__ GridParams shared_grid;
  __shared__ double sum_scratch[kWarps][2];
  __shared__ unsigned count_scratch[kWarps];
  __shared__ int kept_count;
  extern __shared__ __align__(16) unsigned char dynamic[];

  cg::cluster_group cluster = cg::this_cluster();
  const int tid = threadIdx.x, lane = tid & 31, warp = tid >> 5;
  const int cavity = blockIdx.z;
  const int tx = blockIdx.x, ty = blockIdx.y;
  const int ti0 = tx * TILE, tj0 = ty * TILE, ti1 = ti0 + TILE - 1, tj1 = tj0 + TILE - 1;
  const int ranks = f.cluster_x * f.cluster_y;
  const int rank = static_cast<int>(cluster.block_rank());
  const int cx0 = tx - tx % f.cluster_x, cy0 = ty - ty % f.cluster_y;     // the cluster's tiles
  const int block = ty * gridDim.x + tx, blocks = gridDim.x * gridDim.y;  // in the cavity
  const int capacity = b.column_capacity;
  const int slice = f.slice_vertices;
  const FusedLayout layout = fused_layout<Real>(sizeof(RasterStage<Real, kThreads>), kThreads,
                                                slice, capacity, f.item_capacity);
  auto& stage = *reinterpret_cast<RasterStage<Real, kThreads>*>(dynamic);
  Item<Real>* items = reinterpret_cast<Item<Real>*>(dynamic + layout.items);
  int2* table_xy = reinterpret_cast<int2*>(dynamic + layout.xy);
  Real* table_z = reinterpret_cast<Real*>(dynamic + layout.z);
  Real* s_z = reinterpret_cast<Real*>(dynamic + layout.hit_z);
  int* s_tag = reinterpret_cast<int*>(dynamic + layout.hit_tag);
  int* s_count = reinterpret_cast<int*>(dynamic + layout.hit_count);

  const bool inline_ranges = cavity < FusedArgs<Real>::kInlineCavities;
  const int v0 = inline_ranges ? f.inline_vertex_begin[cavity] : f.vertex_begin[cavity];
  const int num_vertices =
      (inline_ranges ? f.inline_vertex_begin[cavity + 1] : f.vertex_begin[cavity + 1]) - v0;
  const int t0 = inline_ranges ? f.inline_triangle_begin[cavity] : b.cavity_triangle_begin[cavity];
  const int num_triangles =
      (inline_ranges ? f.inline_triangle_begin[cavity + 1] : b.cavity_triangle_begin[cavity + 1]) -
      t0;
  // This block's vertices (slice of the table) and triangles (Step 2), by its rank.
  const int vs0 = min(rank * slice, num_vertices), vs1 = min(vs0 + slice, num_vertices);
  const int ts0 = static_cast<int>(static_cast<long long>(num_triangles) * rank / ranks);
  const int ts1 = static_cast<int>(static_cast<long long>(num_triangles) * (rank + 1) / ranks);

  // Loads that depend on nothing, issued first: this thread's first vertex and triangles.
  const bool own_vertex = vs0 + tid < vs1;
  const Vec3 p = load_vec3(b.xyz, v0 + (own_vertex ? vs0 + tid : 0));
  const bool own_triangle = ts0 + tid < ts1;
  const unsigned long long packed = own_triangle ? __ldg(&f.corners[t0 + ts0 + tid]) : 0ull;
  const Vec3 origin = load_vec3(b.xyz, v0);

  // Step 1: the box of this block's vertices, then of the cluster's (all of them).
  double box[6] = {INFINITY, -INFINITY, INFINITY, -INFINITY, INFINITY, -INFINITY};
  for (int v = vs0 + tid; v < vs1; v += kThreads) {
    const Vec3 q = v == vs0 + tid ? p : load_vec3(b.xyz, v0 + v);
    const double c[3] = {dot_rn(q, b.frame.e1), dot_rn(q, b.frame.e2), dot_rn(q, b.frame.up)};
    for (int d = 0; d < 3; ++d) {
      box[2 * d] = fmin(box[2 * d], c[d]);
      box[2 * d + 1] = fmax(box[2 * d + 1], c[d]);
    }
  }
  for (int d = 16; d > 0; d >>= 1) {
    for (int k = 0; k < 6; k += 2) {
      box[k] = fmin(box[k], __shfl_xor_sync(kFullMask, box[k], d));
      box[k + 1] = fmax(box[k + 1], __shfl_xor_sync(kFullMask, box[k + 1], d));
    }
  }
  if (lane == 0) {
    for (int k = 0; k < 6; ++k) box_scratch[warp][k] = box[k];
  }
  __syncthreads();
  if (warp == 0) {
    for (int k = 0; k < 6; k += 2) {
      box[k] = lane < kWarps ? box_scratch[lane][k] : INFINITY;
      box[k + 1] = lane < kWarps ? box_scratch[lane][k + 1] : -INFINITY;
    }
    for (int d = 16; d > 0; d >>= 1) {
      for (int k = 0; k < 6; k += 2) {
        box[k] = fmin(box[k], __shfl_xor_sync(kFullMask, box[k], d));
        box[k + 1] = fmax(box[k + 1], __shfl_xor_sync(kFullMask, box[k + 1], d));
      }
    }
    if (lane < 6) part_box[lane] = box[lane];  // lanes hold the same box after the xor tree
  }
  if (tid == 0) kept_count = 0;
  // The signed volume (relative to the cavity's first vertex) is summed by the blocks of the
  // cavity's first cluster, each over its slice of the triangles (Step 2 below).
  const bool volume_cluster = tx < f.cluster_x && ty < f.cluster_y;
  double volume6 = 0.0;
  // The cluster's barrier is split: the clearing of the next call's accumulators runs while
  // the other blocks arrive.
  cluster.barrier_arrive();
  // The next call's accumulators.
  {
    const int stride = blocks * gridDim.z * kThreads;
    const int first = (cavity * blocks + block) * kThreads + tid;
    for (int k = first; k < f.next_out_count; k += stride) f.next_out[k] = 0;
    for (int k = first; k < b.num_cavities * kStripes; k += stride) {
      CavityState& s = f.next_cavities[k / kStripes];
      s.sum_heights[k % kStripes] = 0.0;
      s.unmatched[k % kStripes] = 0;
      s.volume6[k % kStripes] = 0.0;
    }
    if (first == 0) *f.next_status = Status{0, 0, {0, 0}};
  }

  cluster.barrier_wait();
  if (warp == 0) {
    for (int k = 0; k < 6; k += 2) {
      box[k] = INFINITY;
      box[k + 1] = -INFINITY;
    }
    if (lane < ranks) {
      const double* remote = cluster.map_shared_rank(part_box, lane);
      for (int k = 0; k < 6; k += 2) {
        box[k] = remote[k];
        box[k + 1] = remote[k + 1];
      }
    }
    for (int d = kMaxCluster / 2; d > 0; d >>= 1) {
      for (int k = 0; k < 6; k += 2) {
        box[k] = fmin(box[k], __shfl_xor_sync(kFullMask, box[k], d));
        box[k + 1] = fmax(box[k + 1], __shfl_xor_sync(kFullMask, box[k + 1], d));
      }
    }
    if (lane == 0) {
      shared_grid = make_grid(box[0], box[1], box[2], box[3], box[4], box[5], b.n,
                              static_cast<double>(f.orientation[cavity]));
      if (block == 0) b.cavities[cavity].grid = shared_grid;
    }
  }
  __syncthreads();
  const GridParams grid = shared_grid;
  const int sub_bits = grid.sub_bits;

  // Step 1, snapping: this block's slice of the vertex table.
  if (!grid.empty) {
    const int units = grid.n << sub_bits;
    for (int v = vs0 + tid; v < vs1; v += kThreads) {
      const Vec3 q = v == vs0 + tid ? p : load_vec3(b.xyz, v0 + v);
      table_xy[v - vs0] = make_int2(snap(dot_rn(q, b.frame.e1), grid.a0, grid.scale_a, units),
                                    snap(dot_rn(q, b.frame.e2), grid.b0, grid.scale_b, units));
      table_z[v - vs0] = static_cast<Real>(dot_rn(q, b.frame.up) - grid.u0);
    }
  }
  cluster.barrier_arrive();
  s_count[tid] = 0;
  cluster.barrier_wait();

  // Step 2 for this block's slice of the triangles; each goes to the items of the cluster's
  // tiles that its box meets.
  const int ctx1 = min(cx0 + f.cluster_x, f.tiles_per_side) - 1;
  const int cty1 = min(cy0 + f.cluster_y, f.tiles_per_side) - 1;
  for (int t = ts0 + tid; t < ts1; t += kThreads) {
    int c[3];
    unpack_corners(t == ts0 + tid ? packed : __ldg(&f.corners[t0 + t]), c);
    // The volume's positions are loaded first and used last: their latency overlaps the
    // reads of the vertex table.
    Vec3 pa{}, pb{}, pc{};
    if (volume_cluster) {
      pa = load_vec3(b.xyz, v0 + c[0]);
      pb = load_vec3(b.xyz, v0 + c[1]);
      pc = load_vec3(b.xyz, v0 + c[2]);
    }
    if (grid.empty) {
      if (volume_cluster) volume6 += signed_volume6(pa, pb, pc, origin);
      continue;
    }
    int sx[3], sy[3];
    Real z[3];
    for (int k = 0; k < 3; ++k) {
      const int owner = c[k] / slice, local = c[k] - owner * slice;
      const int2 q = cluster.map_shared_rank(table_xy, owner)[local];
      z[k] = cluster.map_shared_rank(table_z, owner)[local];
      sx[k] = q.x;
      sy[k] = q.y;
    }
    if (volume_cluster) volume6 += signed_volume6(pa, pb, pc, origin);
    SnappedTriangle st;
    if (!setup_triangle(sx, sy, grid.orientation, grid.n, sub_bits, &st)) continue;
    const int x0 = max(st.i0 >> kTileBits, cx0), x1 = min(st.i1 >> kTileBits, ctx1);
    const int y0 = max(st.j0 >> kTileBits, cy0), y1 = min(st.j1 >> kTileBits, cty1);
    if (st.i0 > st.i1 || st.j0 > st.j1 || x0 > x1 || y0 > y1) continue;
    // Corner 0 stays, 1 and 2 may have swapped (selects: registers).
    const bool flip = st.corner[1] == 2;
    union {
      Item<Real> item;
      int4 words[kItemWords<Real>];
    } u;
    for (int k = 0; k < 3; ++k) {
      u.item.x[k] = st.x[k];
      u.item.y[k] = st.y[k];
    }
    u.item.vertex[0] = c[0];
    u.item.vertex[1] = flip ? c[2] : c[1];
    u.item.vertex[2] = flip ? c[1] : c[2];
    u.item.z[0] = z[0];
    u.item.z[1] = flip ? z[2] : z[1];
    u.item.z[2] = flip ? z[1] : z[2];
    u.item.flags = static_cast<int>(st.e_min[0] | (st.e_min[1] << 1) | (st.e_min[2] << 2)) |
                   (st.bottom ? 8 : 0);
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const int target = (x - cx0) + (y - cy0) * f.cluster_x;
        const int slot = atomicAdd(cluster.map_shared_rank(&kept_count, target), 1);
        if (slot < f.item_capacity) {
          int4* dst = reinterpret_cast<int4*>(cluster.map_shared_rank(items, target) + slot);
#pragma unroll
          for (int w = 0; w < kItemWords<Real>; ++w) dst[w] = u.words[w];
        }
      }
    }
  }
  cluster.sync();  // no block reads another's shared memory after this
  const int kept = kept_count;
  const bool overflow = kept > f.item_capacity;
  const bool inside = ti0 < grid.n && tj0 < grid.n;

  // Steps 3-4 by rounds of kThreads items: each thread stages one item with its candidate
  // rectangle in the tile and its height plane, and the block tests the round's candidates.
  if (!grid.empty && inside && !overflow) {
    const int half = 1 << (sub_bits - 1);
    for (int first = 0; first < kept; first += kThreads) {
      const int k = first + tid;
      int count = 0, ci = 0, cj = 0, width = 0, flags = 0;
      int x[3] = {0, 0, 0}, y[3] = {0, 0, 0};
      Real z[3] = {0, 0, 0};
      if (k < kept) {
        const Item<Real>& t = items[k];
        for (int q = 0; q < 3; ++q) {
          x[q] = t.x[q];
          y[q] = t.y[q];
          z[q] = t.z[q];
        }
        flags = t.flags;
        // The box's columns, as setup_triangle found them (the grid clamps nothing inside the
        // tile that the box meets).
        const int xmin = min(x[0], min(x[1], x[2])), xmax = max(x[0], max(x[1], x[2]));
        const int ymin = min(y[0], min(y[1], y[2])), ymax = max(y[0], max(y[1], y[2]));
        ci = max(-((half - xmin) >> sub_bits), ti0);
        cj = max(-((half - ymin) >> sub_bits), tj0);
        width = min((xmax - half) >> sub_bits, ti1) - ci + 1;
        const int height = min((ymax - half) >> sub_bits, tj1) - cj + 1;
        if (width > 0 && height > 0) count = width * height;
      }
      int offset, total;
      Scan(scan_storage).ExclusiveSum(count, offset, total);
      stage_entry<Real, TILE>(stage, tid, x, y, z, flags, k, ci, cj, count > 0 ? width : 0, ti0,
                              tj0, sub_bits, 0);
      stage.offset[tid] = offset;
      if (tid == 0) stage.offset[kThreads] = total;
      __syncthreads();
      raster_round<Real, TILE>(stage, kThreads, total, s_z, s_tag, s_count, capacity);
      __syncthreads();  // the stage and the scan storage are free again
    }
  }

  // Step 5, one column per thread.
  double sum_heights = 0.0;
  unsigned unmatched = 0;
  if (overflow) {
    if (tid == 0) atomicMax(&b.status->max_tile_count, kept);
  } else if (kept > 0 && inside) {
    int n = s_count[tid];
    if (n > capacity) {
      atomicMax(&b.status->max_column_hits, n);
      n = capacity;
    }
    resolve_column(b, ColumnHits<Real>{s_z + tid, s_tag + tid, kThreads}, n, ti0 + tid % TILE,
                   tj0 + tid / TILE, grid, sum_heights, unmatched, ItemFloors<Real>{items, v0});
  }

  // The block's sums: section heights, unpaired columns, its slice of the signed volume.
  for (int d = 16; d > 0; d >>= 1) {
    sum_heights += __shfl_xor_sync(kFullMask, sum_heights, d);
    volume6 += __shfl_xor_sync(kFullMask, volume6, d);
    unmatched += __shfl_xor_sync(kFullMask, unmatched, d);
  }
  if (lane == 0) {
    sum_scratch[warp][0] = sum_heights;
    sum_scratch[warp][1] = volume6;
    count_scratch[warp] = unmatched;
  }
  __syncthreads();
  if (tid == 0) {
    double sum = 0.0, volume = 0.0;
    unsigned u = 0;
    for (int w = 0; w < kWarps; ++w) {
      sum += sum_scratch[w][0];
      volume += sum_scratch[w][1];
      u += count_scratch[w];
    }
    CavityState& s = b.cavities[cavity];
    const int stripe = block % kStripes;
    if (sum != 0.0) atomicAdd(&s.sum_heights[stripe], sum);
    if (volume != 0.0) atomicAdd(&s.volume6[stripe], volume);
    if (u) atomicAdd(&s.unmatched[stripe], static_cast<unsigned long long>(u));
  }
}

template <typename Real, int TILE>
size_t shared_bytes(int slice_vertices, int column_capacity, int item_capacity) {
  return fused_layout<Real>(sizeof(RasterStage<Real, TILE * TILE>), TILE * TILE, slice_vertices,
                            column_capacity, item_capacity)
      .total;
}

int padded(int tiles, int cluster) { return (tiles + cluster - 1) / cluster * cluster; }

template <typename Real, int TILE>
void launch(const Batch<Real>& b, const FusedArgs<Real>& f, cudaStream_t stream) {
  cudaLaunchConfig_t config = {};
  config.gridDim = dim3(padded(f.tiles_per_side, f.cluster_x),
                        padded(f.tiles_per_side, f.cluster_y), b.num_cavities);
  config.blockDim = dim3(TILE * TILE);
  config.dynamicSmemBytes =
      shared_bytes<Real, TILE>(f.slice_vertices, b.column_capacity, f.item_capacity);
  config.stream = stream;
  cudaLaunchAttribute attribute[1];
  attribute[0].id = cudaLaunchAttributeClusterDimension;
  attribute[0].val.clusterDim.x = f.cluster_x;
  attribute[0].val.clusterDim.y = f.cluster_y;
  attribute[0].val.clusterDim.z = 1;
  config.attrs = attribute;
  config.numAttrs = 1;
  cudaLaunchKernelEx(&config, fused_kernel<Real, TILE>, b, f);
}

template <typename Real, int TILE>
int clusters(int cluster_x, int cluster_y, size_t bytes) {
  auto kernel = fused_kernel<Real, TILE>;
  if (cudaFuncSetAttribute(kernel, cudaFuncAttributeMaxDynamicSharedMemorySize,
                           static_cast<int>(bytes)) != cudaSuccess ||
      cudaFuncSetAttribute(kernel, cudaFuncAttributeNonPortableClusterSizeAllowed, 1) !=
          cudaSuccess) {
    cudaGetLastError();
    return 0;
  }
  cudaLaunchConfig_t config = {};
  config.gridDim = dim3(cluster_x, cluster_y, 1);
  config.blockDim = dim3(TILE * TILE);
  config.dynamicSmemBytes = bytes;
  cudaLaunchAttribute attribute[1];
  attribute[0].id = cudaLaunchAttributeClusterDimension;
  attribute[0].val.clusterDim.x = cluster_x;
  attribute[0].val.clusterDim.y = cluster_y;
  attribute[0].val.clusterDim.z = 1;
  config.attrs = attribute;
  config.numAttrs = 1;
  int count = 0;
  if (cudaOccupancyMaxActiveClusters(&count, kernel, &config) != cudaSuccess) {
    cudaGetLastError();
    return 0;
  }
  return count;
}

}  // namespace

template <typename Real>
void launch_fused(const Batch<Real>& b, const FusedArgs<Real>& f, int tile_bits,
                  cudaStream_t stream) {
  if (tile_bits == 3) {
    launch<Real, 8>(b, f, stream);
  } else {
    launch<Real, 16>(b, f, stream);
  }
}

template <typename Real>
size_t fused_shared_bytes(int tile_bits, int slice_vertices, int column_capacity,
                          int item_capacity) {
  if (tile_bits == 3) return shared_bytes<Real, 8>(slice_vertices, column_capacity, item_capacity);
  return shared_bytes<Real, 16>(slice_vertices, column_capacity, item_capacity);
}

template <typename Real>
int fused_clusters(int tile_bits, int cluster_x, int cluster_y, size_t bytes) {
  if (tile_bits == 3) return clusters<Real, 8>(cluster_x, cluster_y, bytes);
  return clusters<Real, 16>(cluster_x, cluster_y, bytes);
}

#define FW_INSTANTIATE(Real)                                                                       \
  template void launch_fused<Real>(const Batch<Real>&, const FusedArgs<Real>&, int, cudaStream_t); \
  template size_t fused_shared_bytes<Real>(int, int, int, int);                                    \
  template int fused_clusters<Real>(int, int, int, size_t);
FW_INSTANTIATE(float)
FW_INSTANTIATE(double)
#undef FW_INSTANTIATE

}  // namespace fluidweight::detail::gpu
