// Steps 1-5 in one launch, for cavities small enough that every block can afford to look at all
// the triangles of its cavity (docs/fluidweight.md, "The fused kernel").
//
// A block owns a tile of TILE x TILE columns of one cavity (blockIdx.x the tile, blockIdx.y the
// cavity). It reduces the cavity's projected box itself (every block of the cavity alike, from
// the positions that all of them read through L2), snaps every vertex of the cavity into a
// table in shared memory (the same snap as geometry.hpp, per vertex instead of per corner),
// sets up (setup_triangle) every triangle whose snapped box meets its tile, rasterizes them by
// rounds with the load-balanced search of tile_raster.cuh and resolves its columns (Step 5,
// resolve.cuh) in shared memory; only the nodal weights leave the chip, by atomics.
//
// Two things the other kernels take from a first kernel are found otherwise:
// - Step 2's orientation (the sign of the signed volume) is assumed per cavity (+1 at first,
//   then the sign of the previous call) while the signed volume is summed by all blocks, each
//   a slice of the triangles; the host compares and runs the call again in the rare case the
//   sign changed (as it does when a buffer overflows).
// - The accumulators (nodal weights, volume sums, status) alternate between two sets: each
//   call clears the set of the next one.
#include <cub/block/block_scan.cuh>

#include "resolve.cuh"
#include "tile_raster.cuh"

namespace fluidweight::detail::gpu {
namespace {

constexpr unsigned long long kCornerMask = (1ull << 21) - 1;

__device__ __forceinline__ void unpack_corners(unsigned long long packed, int (&c)[3]) {
  c[0] = static_cast<int>(packed & kCornerMask);
  c[1] = static_cast<int>((packed >> 21) & kCornerMask);
  c[2] = static_cast<int>(packed >> 42);
}

// Offsets in the dynamic shared memory: the raster stage, the tile's triangles kept for
// Step 5 (counter-clockwise corners, packed), the vertex table (snapped x, y and height) and
// the hits per column (slot-major) with their counts.
struct FusedLayout {
  size_t items, xy, z, hit_z, hit_tag, hit_count, total;
};

__host__ __device__ inline size_t align16(size_t x) { return (x + 15) / 16 * 16; }

template <typename Real>
__host__ __device__ inline FusedLayout fused_layout(size_t stage_bytes, int threads,
                                                    int max_vertices, int capacity,
                                                    int item_capacity) {
  FusedLayout l;
  l.items = align16(stage_bytes);
  l.xy = align16(l.items + sizeof(unsigned long long) * item_capacity);
  l.z = align16(l.xy + sizeof(int2) * max_vertices);
  l.hit_z = align16(l.z + sizeof(Real) * max_vertices);
  l.hit_tag = align16(l.hit_z + sizeof(Real) * capacity * threads);
  l.hit_count = align16(l.hit_tag + sizeof(int) * capacity * threads);
  l.total = align16(l.hit_count + sizeof(int) * threads);
  return l;
}

// Floors for Step 5: a kept triangle's corners from the item list, their snapped coordinates
// from the vertex table.
struct FusedFloors {
  const unsigned long long* items;
  const int2* xy;
  int first_vertex;
  __device__ FloorAtColumn operator()(int item, int px, int py) const {
    int c[3];
    unpack_corners(items[item], c);
    FloorAtColumn f;
    f.key = item;
    for (int k = 0; k < 3; ++k) f.vertex[k] = first_vertex + c[k];
    const int2 p0 = xy[c[0]], p1 = xy[c[1]], p2 = xy[c[2]];
    f.e[0] = edge_function(p1.x, p1.y, p2.x, p2.y, px, py);
    f.e[1] = edge_function(p2.x, p2.y, p0.x, p0.y, px, py);
    f.e[2] = edge_function(p0.x, p0.y, p1.x, p1.y, px, py);
    return f;
  }
};

// Blocks an SM should hold: shared memory allows one of 1024 threads, about two of 256.
constexpr int min_blocks(int tile) { return tile == 32 ? 1 : tile == 16 ? 2 : 8; }

template <typename Real, int TILE>
__global__ void __launch_bounds__(TILE* TILE, min_blocks(TILE))
    fused_kernel(Batch<Real> b, FusedArgs<Real> f) {
  constexpr int kThreads = TILE * TILE;
  constexpr int kWarps = kThreads / 32;
  using Scan = cub::BlockScan<int, kThreads>;
  __shared__ typename Scan::TempStorage scan_storage;
  __shared__ double box_scratch[kWarps][6];
  __shared__ double sum_scratch[kWarps][2];
  __shared__ unsigned count_scratch[kWarps];
  __shared__ int kept_count;
  extern __shared__ __align__(16) unsigned char dynamic[];

  const int tid = threadIdx.x, lane = tid & 31, warp = tid >> 5;
  const int cavity = blockIdx.y;
  const int tile = blockIdx.x, blocks = gridDim.x;
  const int ti0 = (tile % f.tiles_per_side) * TILE, tj0 = (tile / f.tiles_per_side) * TILE;
  const int ti1 = ti0 + TILE - 1, tj1 = tj0 + TILE - 1;
  const int capacity = b.column_capacity;
  const FusedLayout layout = fused_layout<Real>(sizeof(RasterStage<Real, kThreads>), kThreads,
                                                f.max_vertices, capacity, f.item_capacity);
  auto& stage = *reinterpret_cast<RasterStage<Real, kThreads>*>(dynamic);
  unsigned long long* items = reinterpret_cast<unsigned long long*>(dynamic + layout.items);
  int2* table_xy = reinterpret_cast<int2*>(dynamic + layout.xy);
  Real* table_z = reinterpret_cast<Real*>(dynamic + layout.z);
  Real* s_z = reinterpret_cast<Real*>(dynamic + layout.hit_z);
  int* s_tag = reinterpret_cast<int*>(dynamic + layout.hit_tag);
  int* s_count = reinterpret_cast<int*>(dynamic + layout.hit_count);

  // The next call's accumulators.
  {
    const int stride = gridDim.x * gridDim.y * kThreads;
    const int first = (blockIdx.y * gridDim.x + blockIdx.x) * kThreads + tid;
    for (int k = first; k < f.next_out_count; k += stride) f.next_out[k] = 0;
    for (int k = first; k < b.num_cavities * kStripes; k += stride) {
      CavityState& s = f.next_cavities[k / kStripes];
      s.sum_heights[k % kStripes] = 0.0;
      s.unmatched[k % kStripes] = 0;
      s.volume6[k % kStripes] = 0.0;
    }
    if (first == 0) *f.next_status = Status{0, 0, {0, 0}};
  }

  const int v0 = f.vertex_begin[cavity], num_vertices = f.vertex_begin[cavity + 1] - v0;
  const int t0 = b.cavity_triangle_begin[cavity];
  const int num_triangles = b.cavity_triangle_begin[cavity + 1] - t0;
  // Loads in flight together: vertices and triangles are taken kBatch per thread at a time.
  constexpr int kBatch = kThreads >= 1024 ? 4 : 8;

  // Step 1: the projected box of the cavity (exact: min and max), every block alike; and this
  // block's slice of the signed volume (relative to the cavity's first vertex), its loads
  // issued while the box's are in flight.
  double box[6] = {INFINITY, -INFINITY, INFINITY, -INFINITY, INFINITY, -INFINITY};
  double volume6 = 0.0;
  for (int first = 0; first < num_vertices; first += kBatch * kThreads) {
    Vec3 p[kBatch];
#pragma unroll
    for (int q = 0; q < kBatch; ++q) {
      const int v = first + q * kThreads + tid;
      p[q] = load_vec3(b.xyz, v0 + min(v, num_vertices - 1));
    }
    if (first == 0) {
      const int begin = static_cast<int>(static_cast<long long>(num_triangles) * tile / blocks);
      const int end = static_cast<int>(static_cast<long long>(num_triangles) * (tile + 1) / blocks);
      const Vec3 o = load_vec3(b.xyz, v0);
      for (int t = begin + tid; t < end; t += kThreads) {
        int c[3];
        unpack_corners(f.corners[t0 + t], c);
        const Vec3 a = load_vec3(b.xyz, v0 + c[0]), q = load_vec3(b.xyz, v0 + c[1]),
                   r = load_vec3(b.xyz, v0 + c[2]);
        const double ax = a.x - o.x, ay = a.y - o.y, az = a.z - o.z;
        const double bx = q.x - o.x, by = q.y - o.y, bz = q.z - o.z;
        const double cx = r.x - o.x, cy = r.y - o.y, cz = r.z - o.z;
        volume6 += ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
      }
    }
#pragma unroll
    for (int q = 0; q < kBatch; ++q) {
      // A clamped index repeats the last vertex: min and max are unchanged.
      const double c[3] = {dot_rn(p[q], b.frame.e1), dot_rn(p[q], b.frame.e2),
                           dot_rn(p[q], b.frame.up)};
      for (int d = 0; d < 3; ++d) {
        box[2 * d] = fmin(box[2 * d], c[d]);
        box[2 * d + 1] = fmax(box[2 * d + 1], c[d]);
      }
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
  if (tid == 0) kept_count = 0;
  __syncthreads();
  for (int w = 0; w < kWarps; ++w) {
    for (int k = 0; k < 6; k += 2) {
      box[k] = fmin(box[k], box_scratch[w][k]);
      box[k + 1] = fmax(box[k + 1], box_scratch[w][k + 1]);
    }
  }
  const GridParams grid = make_grid(box[0], box[1], box[2], box[3], box[4], box[5], b.n,
                                    static_cast<double>(f.orientation[cavity]));
  if (tile == 0 && tid == 0) b.cavities[cavity].grid = grid;
  const int sub_bits = grid.sub_bits;

  bool overflow = false;
  int kept = 0;  // triangles whose box meets the tile (item indices 0 .. kept - 1)
  if (!grid.empty && !(b.diagnostic_phases & 4)) {
    // The vertex table: snapped coordinates and heights, as make_devtri computes them.
    const int units = grid.n << sub_bits;
    for (int first = 0; first < num_vertices; first += kBatch * kThreads) {
      Vec3 p[kBatch];
#pragma unroll
      for (int q = 0; q < kBatch; ++q) {
        const int v = first + q * kThreads + tid;
        if (v < num_vertices) p[q] = load_vec3(b.xyz, v0 + v);
      }
#pragma unroll
      for (int q = 0; q < kBatch; ++q) {
        const int v = first + q * kThreads + tid;
        if (v < num_vertices) {
          table_xy[v] = make_int2(snap(dot_rn(p[q], b.frame.e1), grid.a0, grid.scale_a, units),
                                  snap(dot_rn(p[q], b.frame.e2), grid.b0, grid.scale_b, units));
          table_z[v] = static_cast<Real>(dot_rn(p[q], b.frame.up) - grid.u0);
        }
      }
    }
    s_count[tid] = 0;
    __syncthreads();

    // The triangles whose box (as setup_triangle finds it) meets the tile, appended to the
    // item list (warp-aggregated; their order does not matter).
    const int half = 1 << (sub_bits - 1);
    const int last = grid.n - 1;
    for (int first = 0; first < num_triangles; first += kBatch * kThreads) {
      unsigned long long packed[kBatch];
#pragma unroll
      for (int q = 0; q < kBatch; ++q) {
        const int t = first + q * kThreads + tid;
        packed[q] = t < num_triangles ? __ldg(&f.corners[t0 + t]) : ~0ull;
      }
#pragma unroll
      for (int q = 0; q < kBatch; ++q) {
        bool keep = false;
        if (packed[q] != ~0ull) {
          int c[3];
          unpack_corners(packed[q], c);
          const int2 p0 = table_xy[c[0]], p1 = table_xy[c[1]], p2 = table_xy[c[2]];
          const int xmin = min(p0.x, min(p1.x, p2.x)), xmax = max(p0.x, max(p1.x, p2.x));
          const int ymin = min(p0.y, min(p1.y, p2.y)), ymax = max(p0.y, max(p1.y, p2.y));
          const int i0 = max(-((half - xmin) >> sub_bits), ti0);
          const int i1 = min(min((xmax - half) >> sub_bits, last), ti1);
          const int j0 = max(-((half - ymin) >> sub_bits), tj0);
          const int j1 = min(min((ymax - half) >> sub_bits, last), tj1);
          keep = i0 <= i1 && j0 <= j1;
        }
        const unsigned ballot = __ballot_sync(kFullMask, keep);
        int base = 0;
        if (lane == 0 && ballot) base = atomicAdd(&kept_count, __popc(ballot));
        base = __shfl_sync(kFullMask, base, 0);
        const int item = base + __popc(ballot & ((1u << lane) - 1));
        if (keep && item < f.item_capacity) items[item] = packed[q];
      }
    }
    __syncthreads();
    kept = kept_count;
    overflow = kept > f.item_capacity;

    // Steps 2-4 by rounds of kThreads items: each thread sets up one triangle (setup_triangle,
    // as the other kernels), stages it with its candidate rectangle and height plane, and the
    // block tests the round's candidates (tile_raster.cuh).
    for (int first = 0; !overflow && first < kept; first += kThreads) {
      const int k = first + tid;
      int count = 0, ci = 0, cj = 0, width = 0, flags = 0;
      Real z0 = 0, dzi = 0, dzj = 0;
      SnappedTriangle st;
      if (k < kept) {
        int c[3];
        unpack_corners(items[k], c);
        int sx[3], sy[3];
        for (int q = 0; q < 3; ++q) {
          const int2 p = table_xy[c[q]];
          sx[q] = p.x;
          sy[q] = p.y;
        }
        if (setup_triangle(sx, sy, grid.orientation, grid.n, sub_bits, &st)) {
          // Corner 0 stays, 1 and 2 may have swapped (selects: registers).
          const bool flip = st.corner[1] == 2;
          const int corner[3] = {c[0], flip ? c[2] : c[1], flip ? c[1] : c[2]};
          items[k] = static_cast<unsigned long long>(corner[0]) |
                     (static_cast<unsigned long long>(corner[1]) << 21) |
                     (static_cast<unsigned long long>(corner[2]) << 42);
          const Real z[3] = {table_z[corner[0]], table_z[corner[1]], table_z[corner[2]]};
          ci = max(st.i0, ti0);
          cj = max(st.j0, tj0);
          width = min(st.i1, ti1) - ci + 1;
          const int height = min(st.j1, tj1) - cj + 1;
          if (width > 0 && height > 0) {
            count = width * height;
            height_plane(st.x, st.y, z, ci, cj, sub_bits, z0, dzi, dzj);
          }
          flags = static_cast<int>(st.e_min[0] | (st.e_min[1] << 1) | (st.e_min[2] << 2)) |
                  (st.bottom ? 8 : 0);
        }
      }
      int offset, total;
      Scan(scan_storage).ExclusiveSum(count, offset, total);
      for (int q = 0; q < 3; ++q) {
        stage.x[q][tid] = st.x[q];
        stage.y[q][tid] = st.y[q];
      }
      stage.flags[tid] = flags;
      stage.ci[tid] = ci;
      stage.cj[tid] = cj;
      stage.width[tid] = width;
      stage.offset[tid] = offset;
      if (tid == 0) stage.offset[kThreads] = total;
      stage.z0[tid] = z0;
      stage.dzi[tid] = dzi;
      stage.dzj[tid] = dzj;
      __syncthreads();
      raster_share<Real, TILE>(stage, kThreads, (b.diagnostic_phases & 1) ? total : 0, first, ti0,
                               tj0, sub_bits, s_z, s_tag, s_count, capacity);
      __syncthreads();  // the stage and the scan storage are free again
    }
  }

  // Step 5, one column per thread.
  double sum_heights = 0.0;
  unsigned unmatched = 0;
  if (overflow) {
    if (tid == 0) atomicMax(&b.status->max_tile_count, kept);
  } else if (kept > 0) {
    int n = (b.diagnostic_phases & 2) ? s_count[tid] : 0;
    if (n > capacity) {
      atomicMax(&b.status->max_column_hits, n);
      n = capacity;
    }
    resolve_column(b, ColumnHits<Real>{s_z + tid, s_tag + tid, kThreads}, n, ti0 + tid % TILE,
                   tj0 + tid / TILE, grid, sum_heights, unmatched,
                   FusedFloors{items, table_xy, v0});
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
    const int stripe = tile % kStripes;
    if (sum != 0.0) atomicAdd(&s.sum_heights[stripe], sum);
    if (volume != 0.0) atomicAdd(&s.volume6[stripe], volume);
    if (u) atomicAdd(&s.unmatched[stripe], static_cast<unsigned long long>(u));
  }
}

template <typename Real, int TILE>
size_t shared_bytes(int max_vertices, int column_capacity, int item_capacity) {
  return fused_layout<Real>(sizeof(RasterStage<Real, TILE * TILE>), TILE * TILE, max_vertices,
                            column_capacity, item_capacity)
      .total;
}

template <typename Real, int TILE>
void launch(const Batch<Real>& b, const FusedArgs<Real>& f, cudaStream_t stream) {
  const dim3 grid(f.tiles_per_side * f.tiles_per_side, b.num_cavities);
  const size_t bytes = shared_bytes<Real, TILE>(f.max_vertices, b.column_capacity, f.item_capacity);
  fused_kernel<Real, TILE><<<grid, TILE * TILE, bytes, stream>>>(b, f);
}

}  // namespace

template <typename Real>
void launch_fused(const Batch<Real>& b, const FusedArgs<Real>& f, int tile_bits,
                  cudaStream_t stream) {
  if (tile_bits == 3) {
    launch<Real, 8>(b, f, stream);
  } else if (tile_bits == 4) {
    launch<Real, 16>(b, f, stream);
  } else {
    launch<Real, 32>(b, f, stream);
  }
}

template <typename Real>
size_t fused_shared_bytes(int tile_bits, int max_vertices, int column_capacity, int item_capacity) {
  if (tile_bits == 3) return shared_bytes<Real, 8>(max_vertices, column_capacity, item_capacity);
  if (tile_bits == 4) return shared_bytes<Real, 16>(max_vertices, column_capacity, item_capacity);
  return shared_bytes<Real, 32>(max_vertices, column_capacity, item_capacity);
}

template <typename Real>
bool allow_fused_shared(int tile_bits, size_t bytes) {
  cudaError_t e;
  if (tile_bits == 3) {
    e = cudaFuncSetAttribute(fused_kernel<Real, 8>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                             static_cast<int>(bytes));
  } else if (tile_bits == 4) {
    e = cudaFuncSetAttribute(fused_kernel<Real, 16>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                             static_cast<int>(bytes));
  } else {
    e = cudaFuncSetAttribute(fused_kernel<Real, 32>, cudaFuncAttributeMaxDynamicSharedMemorySize,
                             static_cast<int>(bytes));
  }
  if (e != cudaSuccess) {
    cudaGetLastError();  // clear it: the caller chooses another tile
    return false;
  }
  return true;
}

#define FW_INSTANTIATE(Real)                                                                       \
  template void launch_fused<Real>(const Batch<Real>&, const FusedArgs<Real>&, int, cudaStream_t); \
  template size_t fused_shared_bytes<Real>(int, int, int, int);                                    \
  template bool allow_fused_shared<Real>(int, size_t);
FW_INSTANTIATE(float)
FW_INSTANTIATE(double)
#undef FW_INSTANTIATE

}  // namespace fluidweight::detail::gpu
