// Step 5 on the GPU, shared by column_kernel (hits in global memory) and tile_kernel (hits in
// shared memory): sort a column's hits, pair the k-th floor with the k-th ceiling, give each
// section's weight to its floor triangle's nodes by barycentric coordinates. With the head
// (column_head, docs/fluidweight.md), the floor carries rho |g| w d (top - z_floor) and the
// ceiling -rho |g| w d (top - z_ceiling): the same net, as column_reference.cpp.
#pragma once

#include "device_common.cuh"

namespace fluidweight::detail::gpu {

// The hits of one column: hit s at z[s * stride], tag[s * stride] (tag: triangle index, or its
// bitwise negation for a floor).
template <typename Real>
struct ColumnHits {
  Real* z;
  int* tag;
  int stride;
};

// Sorts floors first, then ceilings, each by height (insertion sort: usually 2 hits).
// Returns the number of floors.
template <typename Real>
__device__ inline int sort_hits(ColumnHits<Real> h, int n) {
  int floors = 0;
  for (int a = 0; a < n; ++a) {
    Real z = h.z[a * h.stride];
    int tag = h.tag[a * h.stride];
    bool ceiling = tag >= 0;
    floors += !ceiling;
    int b = a;
    for (; b > 0; --b) {
      Real zb = h.z[(b - 1) * h.stride];
      int tb = h.tag[(b - 1) * h.stride];
      bool cb = tb >= 0;
      if (!(cb > ceiling || (cb == ceiling && zb > z))) break;
      h.z[b * h.stride] = zb;
      h.tag[b * h.stride] = tb;
    }
    if (b != a) {
      h.z[b * h.stride] = z;
      h.tag[b * h.stride] = tag;
    }
  }
  return floors;
}

// Sums three values over the lanes of `peers` (lanes with the same key); the lowest lane of
// each group ends with the group's sums. All 32 lanes must call it. A tree over each group's
// lanes in log2 steps (warp-aggregated atomics).
template <typename Real>
__device__ inline void reduce_peers(unsigned peers, Real& a, Real& b, Real& c) {
  const int lane = threadIdx.x & 31;
  unsigned rank = lane ? __popc(peers << (32 - lane)) : 0;  // peers below this lane
  peers &= 0xfffffffeu << lane;                             // peers above it
  while (__any_sync(kFullMask, peers)) {
    int next = __ffs(peers);
    Real ta = __shfl_sync(kFullMask, a, next - 1);
    Real tb = __shfl_sync(kFullMask, b, next - 1);
    Real tc = __shfl_sync(kFullMask, c, next - 1);
    if (next) {
      a += ta;
      b += tb;
      c += tc;
    }
    peers &= ~__ballot_sync(kFullMask, rank & 1);
    rank >>= 1;
  }
}

// Gives each lane's section (when `active`) to its floor triangle: three nodal weights,
// summed over the warp's lanes with the same floor (`key`) before the atomics.
template <typename Real>
__device__ inline void add_section(const Batch<Real>& b, bool active, int key, const int v[3],
                                   const Real w_in[3]) {
  const int lane = threadIdx.x & 31;
  Real w[3] = {w_in[0], w_in[1], w_in[2]};
  unsigned peers = __match_any_sync(kFullMask, active ? key : -1 - lane);
  reduce_peers(peers, w[0], w[1], w[2]);
  if (active && lane == __ffs(peers) - 1) {
    for (int k = 0; k < 3; ++k) atomicAdd(&b.out[v[k]], w[k]);
  }
}

// A floor triangle as Step 5 needs it: a key unique in the batch (its index), its corners'
// vertices and its edge functions at the column centre.
struct FloorAtColumn {
  int key;
  int vertex[3];
  int64_t e[3];
};

// The floor from the triangles written by the setup kernel.
template <typename Real>
struct GlobalFloors {
  const Batch<Real>& b;
  __device__ FloorAtColumn operator()(int tri, int px, int py) const {
    const DevTri<Real> t = load_tri(&b.tris[tri]);
    FloorAtColumn f;
    f.key = tri;
    for (int k = 0; k < 3; ++k) f.vertex[k] = t.vertex[k];
    covers_column(t, px, py, f.e);
    return f;
  }
};

// Step 5 for one column per lane (n = 0 for lanes without a column). All 32 lanes must call
// it. A hit's tag is `floor_of(~tag, px, py)`'s argument for floors. Adds the column's section
// heights to sum_heights and counts an unpaired column.
template <typename Real, typename Floors>
__device__ inline void resolve_column(const Batch<Real>& b, ColumnHits<Real> h, int n, int i, int j,
                                      const GridParams& grid, double& sum_heights,
                                      unsigned& unmatched, const Floors& floor_of) {
  int floors = n ? sort_hits(h, n) : 0;
  int ceilings = n - floors;
  int sections = floors < ceilings ? floors : ceilings;
  unmatched += floors != ceilings;
  int rounds = __reduce_max_sync(kFullMask, sections);
  const int px = column_centre(i, grid.sub_bits), py = column_centre(j, grid.sub_bits);
  const Real weight_per_height = static_cast<Real>(b.rho_g * grid.cell_area);
  const Real top = static_cast<Real>(grid.u1 - grid.u0);
  // A triangle's nodal weights at the column for a load `height` times weight_per_height.
  auto spread = [&](const FloorAtColumn& f, Real height, int v[3], Real w[3]) {
    Real scale = weight_per_height * height / static_cast<Real>(f.e[0] + f.e[1] + f.e[2]);
    for (int k = 0; k < 3; ++k) {
      v[k] = f.vertex[k];
      w[k] = scale * static_cast<Real>(f.e[k]);
    }
  };
  for (int r = 0; r < rounds; ++r) {
    bool active = r < sections;
    int key = 0, v[3] = {0, 0, 0};
    Real w[3] = {0, 0, 0};
    Real z_floor = 0, z_ceiling = 0;
    if (active) {
      z_floor = h.z[r * h.stride];
      z_ceiling = h.z[(floors + r) * h.stride];
      sum_heights += z_ceiling - z_floor;
      FloorAtColumn f = floor_of(~h.tag[r * h.stride], px, py);
      key = f.key;
      spread(f, b.head ? top - z_floor : z_ceiling - z_floor, v, w);
    }
    add_section(b, active, key, v, w);
    if (!b.head) continue;  // the same for the whole warp
    if (active) {
      FloorAtColumn c = floor_of(h.tag[(floors + r) * h.stride], px, py);
      key = c.key;
      spread(c, z_ceiling - top, v, w);
    }
    add_section(b, active, key, v, w);
  }
}

}  // namespace fluidweight::detail::gpu
