// Steps 1-2 on the GPU (reduce_kernel, setup_kernel) and the closed-form hydrostatic load.
#include <cub/block/block_reduce.cuh>

#include "device_common.cuh"

namespace fluidweight::detail::gpu {
namespace {

constexpr int kBlock = kSetupBlock;
// A triangle over at most this many tiles is binned by its own lane (warp-aggregated), up to
// kWarpTiles by its whole warp, beyond that it goes to the list that every tile reads.
constexpr int kLaneTiles = 4;
constexpr int kWarpTiles = 256;

struct Box {
  double v[7];  // min e1, max e1, min e2, max e2, min up, max up, 6 x signed volume
};

struct BoxOp {
  __device__ Box operator()(const Box& a, const Box& b) const {
    Box r;
    for (int k = 0; k < 6; k += 2) {
      r.v[k] = fmin(a.v[k], b.v[k]);
      r.v[k + 1] = fmax(a.v[k + 1], b.v[k + 1]);
    }
    r.v[6] = a.v[6] + b.v[6];
    return r;
  }
};

__device__ Box empty_box() {
  Box b;
  for (int k = 0; k < 6; k += 2) {
    b.v[k] = INFINITY;
    b.v[k + 1] = -INFINITY;
  }
  b.v[6] = 0.0;
  return b;
}

using BoxReduce = cub::BlockReduce<Box, kBlock>;

// Step 1: each block reduces a range of one cavity's vertices (projected box) or triangles
// (signed volume, relative to the cavity's first vertex) into its partial. All blocks also
// clear the accumulators of the call. With an assumed orientation (Batch::orientation) the
// host gives no triangle ranges: setup_kernel sums the signed volume from the corners it
// loads anyway, off this kernel's path.
template <typename Real>
__global__ void __launch_bounds__(kBlock)
    reduce_kernel(Batch<Real> b, int zero_out_count, int zero_tile_count) {
  __shared__ typename BoxReduce::TempStorage storage;
  let_next_start();  // setup_kernel's blocks load their corners meanwhile
  const int stride = gridDim.x * blockDim.x;
  const int first = blockIdx.x * blockDim.x + threadIdx.x;
  for (int k = first; k < zero_out_count; k += stride) b.out[k] = 0;
  for (int k = first; k < zero_tile_count; k += stride) b.tile_count[count_slot(k)] = 0;
  for (int k = first; k < b.num_cavities * kStripes; k += stride) {
    b.cavities[k / kStripes].sum_heights[k % kStripes] = 0.0;
    b.cavities[k / kStripes].unmatched[k % kStripes] = 0;
    b.cavities[k / kStripes].volume6[k % kStripes] = 0.0;
  }
  if (first == 0) {
    *b.status = Status{0, 0, {0, 0}};
    if (b.big_count) *b.big_count = 0;
  }

  const ReduceJob job = b.jobs[blockIdx.x];
  Box box = empty_box();
  if (job.kind == 0) {
    for (int v = job.begin + threadIdx.x; v < job.end; v += blockDim.x) {
      Vec3 p = load_vec3(b.xyz, v);
      double c[3] = {dot_rn(p, b.frame.e1), dot_rn(p, b.frame.e2), dot_rn(p, b.frame.up)};
      for (int d = 0; d < 3; ++d) {
        box.v[2 * d] = fmin(box.v[2 * d], c[d]);
        box.v[2 * d + 1] = fmax(box.v[2 * d + 1], c[d]);
      }
    }
  } else {
    Vec3 o = load_vec3(b.xyz, b.cavity_vertex_begin[job.cavity]);
    for (int t = job.begin + threadIdx.x; t < job.end; t += blockDim.x) {
      const int* v = b.triangles + 3 * t;
      box.v[6] +=
          signed_volume6(load_vec3(b.xyz, v[0]), load_vec3(b.xyz, v[1]), load_vec3(b.xyz, v[2]), o);
    }
  }
  box = BoxReduce(storage).Reduce(box, BoxOp());
  if (threadIdx.x == 0) {
    // Component-major, so that block_grids reads them coalesced.
    for (int k = 0; k < 7; ++k) b.partials[k * b.num_jobs + blockIdx.x] = box.v[k];
  }
}

// The grids of the cavities of this block's triangles [first, last], reduced from the
// partials by every block alike (deterministic). The block holding a cavity's first triangle
// also publishes its grid and signed volume (for the later kernels and the host). Returns
// the first cavity; grids[c - first] is cavity c's.
template <typename Real>
__device__ int block_grids(const Batch<Real>& b, int first_triangle, int last_triangle,
                           GridParams* grids, int max_grids) {
  __shared__ typename BoxReduce::TempStorage storage;
  const int c0 = b.tri_cavity[first_triangle], c1 = b.tri_cavity[last_triangle];
  // The first cavity's job range, owner and assumed orientation are the call's inputs: loaded
  // while the previous kernel may still run (launch_overlapped), its partials after it.
  int begin = b.cavity_job_begin[c0], end = b.cavity_job_begin[c0 + 1];
  int owner = b.cavity_triangle_begin[c0], assumed = b.orientation ? b.orientation[c0] : 0;
  wait_previous();  // reduce_kernel's partials (a no-op in a kernel launched the ordinary way)
  for (int c = c0; c <= c1 && c - c0 < max_grids; ++c) {
    if (c > c0) {
      begin = b.cavity_job_begin[c];
      end = b.cavity_job_begin[c + 1];
      owner = b.cavity_triangle_begin[c];
      assumed = b.orientation ? b.orientation[c] : 0;
    }
    Box sum = empty_box();
    for (int k = begin + threadIdx.x; k < end; k += blockDim.x) {
      Box p;
      for (int q = 0; q < 7; ++q) p.v[q] = b.partials[q * b.num_jobs + k];
      sum = BoxOp()(sum, p);
    }
    sum = BoxReduce(storage).Reduce(sum, BoxOp());
    if (threadIdx.x == 0) {
      const double volume = assumed ? assumed : sum.v[6] / 6.0;  // its sign is the orientation
      grids[c - c0] =
          make_grid(sum.v[0], sum.v[1], sum.v[2], sum.v[3], sum.v[4], sum.v[5], b.n, volume);
      if (owner >= first_triangle && owner <= last_triangle) {
        b.cavities[c].grid = grids[c - c0];
        b.cavities[c].signed_volume = volume;
      }
    }
    __syncthreads();
  }
  return c0;
}

// A block's triangles span at most this many cavities (4 triangles at least a cavity).
constexpr int kMaxBlockCavities = kBlock / 4 + 1;

// Step 2 for one triangle; false when it covers no column.
// The triangle's corners (vertex indices v, positions p) are loaded by the caller, before the
// grid is known, so that their loads overlap the reduction of the partials.
template <typename Real>
__device__ bool make_devtri(const Batch<Real>& b, const int (&v)[3], const Vec3 (&p)[3], int cavity,
                            const GridParams& g, DevTri<Real>& d) {
  d = DevTri<Real>{};
  d.flags = cavity << 4;
  d.i0 = d.j0 = 1;
  d.i1 = d.j1 = 0;
  if (g.empty) return false;
  const int units = g.n << g.sub_bits;
  int sx[3], sy[3];
  double z[3];
  for (int k = 0; k < 3; ++k) {
    sx[k] = snap(dot_rn(p[k], b.frame.e1), g.a0, g.scale_a, units);
    sy[k] = snap(dot_rn(p[k], b.frame.e2), g.b0, g.scale_b, units);
    z[k] = dot_rn(p[k], b.frame.up) - g.u0;
  }
  SnappedTriangle s;
  if (!setup_triangle(sx, sy, g.orientation, g.n, g.sub_bits, &s)) return false;
  // Corner 0 stays, 1 and 2 may have swapped (selects, not run-time indices: registers).
  const bool flip = s.corner[1] == 2;
  const int vertex[3] = {v[0], flip ? v[2] : v[1], flip ? v[1] : v[2]};
  const double height[3] = {z[0], flip ? z[2] : z[1], flip ? z[1] : z[2]};
  for (int k = 0; k < 3; ++k) {
    d.x[k] = s.x[k];
    d.y[k] = s.y[k];
    d.vertex[k] = vertex[k];
    d.z[k] = static_cast<Real>(height[k]);
  }
  d.flags |=
      static_cast<int>(s.e_min[0] | (s.e_min[1] << 1) | (s.e_min[2] << 2)) | (s.bottom ? 8 : 0);
  // 16-bit box: an empty one (i1 or j1 may be -1) kept as 1 > 0.
  const bool covers = s.i0 <= s.i1 && s.j0 <= s.j1;
  d.i0 = static_cast<unsigned short>(covers ? s.i0 : 1);
  d.i1 = static_cast<unsigned short>(covers ? s.i1 : 0);
  d.j0 = static_cast<unsigned short>(covers ? s.j0 : 1);
  d.j1 = static_cast<unsigned short>(covers ? s.j1 : 0);
  return covers;
}

// The signed volume (6 x, relative to the cavity's first vertex) of the lanes' triangles,
// summed over the warp when all its lanes hold one cavity, into the cavity's striped
// accumulators (the host checks its sign against the orientation Step 2 assumed).
template <typename Real>
__device__ void add_signed_volume(const Batch<Real>& b, bool valid, int cavity, const Vec3 (&p)[3],
                                  const Vec3& origin) {
  double v6 = valid ? signed_volume6(p[0], p[1], p[2], origin) : 0.0;
  const int stripe = (blockIdx.x * (kBlock / 32) + threadIdx.x / 32) % kStripes;
  const int first = __shfl_sync(kFullMask, cavity, 0);
  if (__all_sync(kFullMask, cavity == first || !valid)) {
    for (int d = 16; d > 0; d >>= 1) v6 += __shfl_xor_sync(kFullMask, v6, d);
    if ((threadIdx.x & 31) == 0 && first >= 0) atomicAdd(&b.cavities[first].volume6[stripe], v6);
  } else if (valid) {
    atomicAdd(&b.cavities[cavity].volume6[stripe], v6);
  }
}

// Appends each lane's triangle t to the tiles tile[0..kLaneTiles) (-1: none): `tiles` tiles of a
// box `width` tiles wide from tile[0] (both at most kLaneTiles: 4 bits each in the key). Lanes
// whose boxes start in the same tile with the same shape list the same tiles, so one match on
// (first tile, shape) groups them for all their tiles (a match per tile made a chain of four
// dependent matches); lanes whose boxes overlap only
// partly take their places by separate atomics (more atomics, each still counting a whole
// group; past the capacity the host grows it).
__device__ void bin_lane_tiles(int* tile_count, int* tile_list, int capacity,
                               const int (&tile)[kLaneTiles], int tiles, int width, int t) {
  const int lane = threadIdx.x & 31;
  const long long key =
      tile[0] >= 0 ? (static_cast<long long>(tile[0]) << 8) | (width << 4) | tiles : -1ll - lane;
  const unsigned peers = __match_any_sync(kFullMask, key);
  const int leader = __ffs(peers) - 1;
  int base[kLaneTiles];
#pragma unroll
  for (int q = 0; q < kLaneTiles; ++q) {
    base[q] = 0;
    if (tile[q] >= 0 && lane == leader)
      base[q] = atomicAdd(&tile_count[count_slot(tile[q])], __popc(peers));
  }
  const int rank = __popc(peers & ((1u << lane) - 1));
#pragma unroll
  for (int q = 0; q < kLaneTiles; ++q) {
    const int pos = __shfl_sync(kFullMask, base[q], leader) + rank;
    if (tile[q] >= 0 && pos < capacity) {
      tile_list[static_cast<size_t>(tile[q]) * capacity + pos] = t;
    }
  }
}

// Step 2 per triangle; the tiled kernel also bins each triangle to the tiles of its box.
template <typename Real>
__global__ void __launch_bounds__(kBlock) setup_kernel(Batch<Real> b, bool bin_to_tiles) {
  using Reduce = cub::BlockReduce<unsigned long long, kBlock>;
  __shared__ typename Reduce::TempStorage storage;
  __shared__ GridParams grids[kMaxBlockCavities];
  // The block's records as 16-byte pieces. With 64-byte records (f32, 4 pieces) piece k of
  // triangle i sits at 4 i + (k + i / 2) % 4, so that eight lanes' stores of one piece meet
  // eight different bank groups, not two (bank conflicts otherwise); 80-byte
  // records (5 pieces) are conflict-free as they are.
  constexpr int kPieces = sizeof(DevTri<Real>) / 16;
  constexpr int kRotate = kPieces == 4 ? 1 : 0;
  __shared__ int4 staged[kBlock * kPieces];
  const int first = blockIdx.x * blockDim.x;
  const int last = min(first + static_cast<int>(blockDim.x), b.num_triangles) - 1;
  const int t = first + threadIdx.x;
  // The triangle's corners first: their loads are in flight while the grid is reduced.
  int v[3] = {0, 0, 0}, cavity = -1;
  Vec3 p[3] = {}, origin = {};
  if (t < b.num_triangles) {
    cavity = b.tri_cavity[t];
    for (int k = 0; k < 3; ++k) v[k] = b.triangles[3 * t + k];
    for (int k = 0; k < 3; ++k) p[k] = load_vec3(b.xyz, v[k]);
    if (b.orientation) origin = load_vec3(b.xyz, b.cavity_vertex_begin[cavity]);
  }
  let_next_start();
  // block_grids waits for reduce_kernel (its partials and cleared accumulators).
  const int c0 = block_grids(b, first, last, grids, kMaxBlockCavities);
  DevTri<Real> d;
  bool valid = false;
  if (t < b.num_triangles) {
    valid = make_devtri(b, v, p, cavity, grids[cavity - c0], d);
    union {
      int4 v[kPieces];
      DevTri<Real> t;
    } u;
    u.t = d;
#pragma unroll
    for (int k = 0; k < kPieces; ++k) {
      staged[threadIdx.x * kPieces + (k + kRotate * (threadIdx.x / 2)) % kPieces] = u.v[k];
    }
  }
  if (b.orientation) add_signed_volume(b, t < b.num_triangles, cavity, p, origin);
  // The block's triangles leave in consecutive 16-byte pieces (coalesced).
  __syncthreads();
  {
    int4* dst = reinterpret_cast<int4*>(b.tris + first);
    const int pieces = (last - first + 1) * kPieces;
    for (int k = threadIdx.x; k < pieces; k += blockDim.x) {
      const int i = k / kPieces;
      dst[k] = staged[i * kPieces + (k % kPieces + kRotate * (i / 2)) % kPieces];
    }
  }
  if (!bin_to_tiles) {
    // The leveraging kernel's c: candidate columns over all triangles' boxes, per block.
    unsigned long long candidates =
        valid ? static_cast<unsigned long long>(d.i1 - d.i0 + 1) * (d.j1 - d.j0 + 1) : 0ull;
    candidates = Reduce(storage).Sum(candidates);
    if (threadIdx.x == 0) b.candidates[blockIdx.x] = candidates;
    return;
  }
  int tx0 = 0, ty0 = 0, width = 0, tiles = 0, base = 0;
  if (valid) {
    tx0 = d.i0 >> b.tile_bits;
    ty0 = d.j0 >> b.tile_bits;
    width = (d.i1 >> b.tile_bits) - tx0 + 1;
    tiles = width * ((d.j1 >> b.tile_bits) - ty0 + 1);
    base = cavity_of(d.flags) * b.tiles_per_side * b.tiles_per_side;
  }
  const bool own = tiles > 0 && tiles <= kLaneTiles;
  int tile[kLaneTiles];
#pragma unroll
  for (int q = 0; q < kLaneTiles; ++q) {
    tile[q] = own && q < tiles ? base + (ty0 + q / width) * b.tiles_per_side + tx0 + q % width : -1;
  }
  bin_lane_tiles(b.tile_count, b.tile_list, b.tile_capacity, tile, own ? tiles : 0, width, t);
  // Larger boxes: the warp's (triangle, tile) pairs laid end to end and shared by its lanes,
  // several pairs in flight at once.
  const int lane = threadIdx.x & 31;
  const bool shared = tiles > kLaneTiles && tiles <= kWarpTiles;
  int count = shared ? tiles : 0, offset = count;
  for (int d = 1; d < 32; d <<= 1) {  // inclusive scan over the warp
    int up = __shfl_up_sync(kFullMask, offset, d);
    if (lane >= d) offset += up;
  }
  const int total = __shfl_sync(kFullMask, offset, 31);
  offset -= count;  // exclusive
  for (int first_pair = 0; first_pair < total; first_pair += 32) {
    const int p = first_pair + lane;
    // The lane whose pairs contain p: the last with offset <= p (binary search by shuffles).
    int owner = 0;
    for (int step = 16; step > 0; step >>= 1) {
      int o = __shfl_sync(kFullMask, offset, (owner + step) & 31);
      if (owner + step < 32 && o <= p) owner += step;
    }
    const int q = p - __shfl_sync(kFullMask, offset, owner);
    const int w = max(1, __shfl_sync(kFullMask, width, owner));
    const int tile = __shfl_sync(kFullMask, base, owner) +
                     (__shfl_sync(kFullMask, ty0, owner) + q / w) * b.tiles_per_side +
                     __shfl_sync(kFullMask, tx0, owner) + q % w;
    const int tri = __shfl_sync(kFullMask, t, owner);
    if (p < total) {
      const int pos = atomicAdd(&b.tile_count[count_slot(tile)], 1);
      if (pos < b.tile_capacity)
        b.tile_list[static_cast<size_t>(tile) * b.tile_capacity + pos] = tri;
    }
  }
  if (tiles > kWarpTiles) b.big_list[atomicAdd(b.big_count, 1)] = t;
}

// Closed-form hydrostatic load (see hydrostatic.cpp): pressure rho |g| depth below the highest
// vertex, f_i = N (p_i + p_1 + p_2 + p_3) / 24 with N oriented outward.
template <typename Real>
__global__ void __launch_bounds__(kBlock) hydrostatic_kernel(Batch<Real> b) {
  __shared__ GridParams grids[kMaxBlockCavities];
  const int first = blockIdx.x * blockDim.x;
  const int last = min(first + static_cast<int>(blockDim.x), b.num_triangles) - 1;
  const int c0 = block_grids(b, first, last, grids, kMaxBlockCavities);
  const int t = first + threadIdx.x;
  if (t >= b.num_triangles) return;
  const GridParams& g = grids[b.tri_cavity[t] - c0];
  const int* v = b.triangles + 3 * t;
  Vec3 x[3];
  double p[3];
  for (int k = 0; k < 3; ++k) {
    x[k] = load_vec3(b.xyz, v[k]);
    p[k] = b.rho_g * (g.u1 - dot_rn(x[k], b.frame.up));
  }
  double ux = x[1].x - x[0].x, uy = x[1].y - x[0].y, uz = x[1].z - x[0].z;
  double wx = x[2].x - x[0].x, wy = x[2].y - x[0].y, wz = x[2].z - x[0].z;
  double s = g.orientation / 24.0;
  double n[3] = {s * (uy * wz - uz * wy), s * (uz * wx - ux * wz), s * (ux * wy - uy * wx)};
  double sum = p[0] + p[1] + p[2];
  for (int k = 0; k < 3; ++k) {
    for (int d = 0; d < 3; ++d) {
      atomicAdd(&b.out[3 * v[k] + d], static_cast<Real>(n[d] * (p[k] + sum)));
    }
  }
}

}  // namespace

template <typename Real>
void launch_reduce(const Batch<Real>& b, int zero_out_count, int zero_tile_count,
                   cudaStream_t stream) {
  reduce_kernel<Real><<<b.num_jobs, kBlock, 0, stream>>>(b, zero_out_count, zero_tile_count);
}

template <typename Real>
void launch_setup(const Batch<Real>& b, bool bin_to_tiles, cudaStream_t stream) {
  launch_overlapped(b.overlap >= 1, setup_kernel<Real>, b.setup_blocks, kBlock, 0, stream, b,
                    bin_to_tiles);
}

template <typename Real>
void launch_hydrostatic(const Batch<Real>& b, cudaStream_t stream) {
  hydrostatic_kernel<Real><<<b.setup_blocks, kBlock, 0, stream>>>(b);
}

#define FW_INSTANTIATE(Real)                                                     \
  template void launch_reduce<Real>(const Batch<Real>&, int, int, cudaStream_t); \
  template void launch_setup<Real>(const Batch<Real>&, bool, cudaStream_t);      \
  template void launch_hydrostatic<Real>(const Batch<Real>&, cudaStream_t);
FW_INSTANTIATE(float)
FW_INSTANTIATE(double)
#undef FW_INSTANTIATE

}  // namespace fluidweight::detail::gpu
