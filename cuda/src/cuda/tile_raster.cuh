// Steps 3-4 inside one tile of TILE x TILE columns, shared by tile_kernel and fused_kernel.
//
// A round of triangles is staged in shared memory, each with its candidate rectangle (the
// columns of its box inside the tile), an exclusive scan of the candidate counts laying all
// candidates of the round end to end. Candidates are then dealt out in warp windows: a warp
// takes 32 consecutive candidates, one a lane, then the 32 that come kThreads later. Every
// lane evaluates its candidate from scratch (no stepping from a previous one), so a lane
// changing triangle costs nothing more than one staying, and the warp never waits for a lane
// setting up a triangle (the earlier contiguous shares spent ~2/3 of their instructions
// there, in whichever lane of the warp entered a new triangle).
//
// The fill rule's test is exact in 32-bit integers: at candidate (ci + li, cj + lj) of a
// triangle's rectangle, edge k's function is E_k(ci, cj) + 2^s (lj dx_k - li dy_k), with
// (dx_k, dy_k) the edge's snapped vector, so E_k >= e_min_k exactly when
// lj dx_k - li dy_k >= ceil((e_min_k - E_k(ci, cj)) / 2^s). The left side stays within
// +-2^30 (|dx|, |dy| <= 2^25, li, lj < 16), so that threshold is clamped to +-2^30 and kept
// in 32 bits. Hits go to per-column slots in shared memory (slot * TILE^2 + column), tagged
// with the triangle's item index (bitwise-negated for floors).
#pragma once

#include <climits>

#include "device_common.cuh"

namespace fluidweight::detail::gpu {

// A round's triangles, entry k:
//   thr[k] = (the three thresholds above, tag), tag = item or ~item for a floor;
//   dx[k] = (dx_0, dx_1, dx_2, rectangle), rectangle = first column in the tile (bits 0-7,
//           (cj - tj0) TILE + ci - ti0) | width << 8;
//   dy[k] = (dy_0, dy_1, dy_2, a word the caller may use);
//   offset[k] its first candidate (offset[m] the round's total);
//   z0, dzi, dzj: the height plane at (ci, cj) and its steps along a row and a column.
// Edge k goes from corner k + 1 to corner k + 2 (mod 3), as in edge_function's callers.
template <typename Real, int N>
struct RasterStage {
  int4 thr[N], dx[N], dy[N];
  int offset[N + 1];
  Real z0[N], dzi[N], dzj[N];
};

// Stages entry k: a triangle with counter-clockwise snapped corners (x, y), heights z, fill
// rule thresholds and floor bit in `flags` (DevTri's bits 0-3), item index `item`, candidate
// rectangle from column (ci, cj), `width` columns wide (0: no candidate) in the tile at
// (ti0, tj0). `spare` goes to dy[k].w.
template <typename Real, int TILE, int N>
__device__ __forceinline__ void stage_entry(RasterStage<Real, N>& s, int k, const int (&x)[3],
                                            const int (&y)[3], const Real (&z)[3], int flags,
                                            int item, int ci, int cj, int width, int ti0, int tj0,
                                            int sub_bits, int spare) {
  int t[3] = {0, 0, 0}, dx[3] = {0, 0, 0}, dy[3] = {0, 0, 0};
  Real z0 = 0, dzi = 0, dzj = 0;
  if (width > 0) {
    const int px = column_centre(ci, sub_bits), py = column_centre(cj, sub_bits);
    Real area = 0;
#pragma unroll
    for (int c = 0; c < 3; ++c) {
      const int p = (c + 1) % 3, q = (c + 2) % 3;
      dx[c] = x[q] - x[p];
      dy[c] = y[q] - y[p];
      const int64_t e = edge_function(x[p], y[p], x[q], y[q], px, py);
      // ceil((e_min - e) / 2^s) by an arithmetic shift (floor), clamped (see above).
      const int64_t need = -((e - ((flags >> c) & 1)) >> sub_bits);
      t[c] = static_cast<int>(max(min(need, int64_t{1} << 30), -(int64_t{1} << 30)));
      // The height plane: barycentric weights at (ci, cj) and their steps, once per triangle.
      const int64_t di = -static_cast<int64_t>(dy[c]) << sub_bits;
      const int64_t dj = static_cast<int64_t>(dx[c]) << sub_bits;
      area += static_cast<Real>(e);
      z0 += static_cast<Real>(e) * z[c];
      dzi += static_cast<Real>(di) * z[c];
      dzj += static_cast<Real>(dj) * z[c];
    }
    const Real inv = Real(1) / area;
    z0 *= inv;
    dzi *= inv;
    dzj *= inv;
  }
  const int tag = is_floor(flags) ? ~item : item;
  const int rect = ((cj - tj0) * TILE + (ci - ti0)) | (width << 8);
  s.thr[k] = make_int4(t[0], t[1], t[2], tag);
  s.dx[k] = make_int4(dx[0], dx[1], dx[2], width > 0 ? rect : 0);
  s.dy[k] = make_int4(dy[0], dy[1], dy[2], spare);
  s.z0[k] = z0;
  s.dzi[k] = dzi;
  s.dzj[k] = dzj;
}

// Steps 3-4 of the staged entries [0, m) with `total` candidates (offset[] filled), by the
// block's TILE^2 threads, all of which must call it.
template <typename Real, int TILE, int N>
__device__ __forceinline__ void raster_round(const RasterStage<Real, N>& s, int m, int total,
                                             Real* s_z, int* s_tag, int* s_count, int capacity) {
  constexpr int kThreads = TILE * TILE;
  const int lane = threadIdx.x & 31;
  int item = 0;  // the entry of the warp's current window start (the same in all lanes)
  for (int base = threadIdx.x & ~31; base < total; base += kThreads) {
    // The 32 entries after `item` (their first candidates), skipping ahead by 32 while all of
    // them start before the window.
    int o, before;
    for (;;) {
      const int e = item + 1 + lane;
      o = e <= m ? s.offset[e] : INT_MAX;
      before = __popc(__ballot_sync(kFullMask, o <= base));
      if (before < 32) break;
      item += 32;
    }
    // This lane's entry: `item`, the `before` entries starting at or before the window, and
    // those starting inside it at or before the lane's candidate: bits of the positions where
    // they start (one reduction, no chain of shuffles; entries without candidates share a
    // start with the next one and are then found by the walk below).
    const int f = base + lane;
    const unsigned starts =
        __reduce_or_sync(kFullMask, o > base && o - base < 32 ? 1u << (o - base) : 0u);
    int own = item + before + __popc(starts & (0xffffffffu >> (31 - lane)));
    item += before;
    if (f >= total) continue;
    while (s.offset[own + 1] <= f) ++own;
    const int q0 = f - s.offset[own];
    const int4 tb = s.thr[own], xb = s.dx[own], yb = s.dy[own];
    const int w = xb.w >> 8;
    // q0 < TILE^2 and w <= TILE: the float quotient is exact after truncation.
    const int lj = __float2int_rz(__fdividef(static_cast<float>(q0) + 0.5f, static_cast<float>(w)));
    const int li = q0 - lj * w;
    if (lj * xb.x - li * yb.x >= tb.x && lj * xb.y - li * yb.y >= tb.y &&
        lj * xb.z - li * yb.z >= tb.z) {
      const int col = (xb.w & 255) + lj * TILE + li;
      const Real z =
          s.z0[own] + s.dzi[own] * static_cast<Real>(li) + s.dzj[own] * static_cast<Real>(lj);
      const int slot = atomicAdd(&s_count[col], 1);
      if (slot < capacity) {
        s_z[slot * kThreads + col] = z;
        s_tag[slot * kThreads + col] = tb.w;
      }
    }
  }
}

}  // namespace fluidweight::detail::gpu
