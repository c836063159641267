// The automatic kernel choice from the candidate columns of a batch's triangle boxes (host code,
// compiled by nvcc with the rest of the CUDA backend).
#include <algorithm>
#include <cmath>

#include "kernel_choice.hpp"

namespace fluidweight::detail {

CandidateCounts candidate_counts(const std::vector<CavityView>& cavities, const Frame& frame,
                                 int n) {
  CandidateCounts counts;
  long long triangles = 0;
  double sum = 0;
  for (const CavityView& v : cavities) {
    std::vector<double> a(v.num_vertices), b(v.num_vertices);
    double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
    for (int k = 0; k < v.num_vertices; ++k) {
      const double* x = v.xyz + 3 * k;
      a[k] = x[0] * frame.e1.x + x[1] * frame.e1.y + x[2] * frame.e1.z;
      b[k] = x[0] * frame.e2.x + x[1] * frame.e2.y + x[2] * frame.e2.z;
      a0 = std::min(a0, a[k]), a1 = std::max(a1, a[k]);
      b0 = std::min(b0, b[k]), b1 = std::max(b1, b[k]);
    }
    const double wa = (a1 - a0) / n, wb = (b1 - b0) / n;
    if (!(wa > 0 && wb > 0)) continue;
    // Columns whose centres (index + 1/2) lie in [lo, hi], in units of a column.
    auto columns = [](double lo, double hi) {
      return std::max(0.0, std::floor(hi - 0.5) - std::ceil(lo - 0.5) + 1);
    };
    for (int t = 0; t < v.num_triangles; ++t) {
      const int* c = v.triangles + 3 * t;
      const double amin = std::min({a[c[0]], a[c[1]], a[c[2]]}),
                   amax = std::max({a[c[0]], a[c[1]], a[c[2]]});
      const double bmin = std::min({b[c[0]], b[c[1]], b[c[2]]}),
                   bmax = std::max({b[c[0]], b[c[1]], b[c[2]]});
      const double box =
          columns((amin - a0) / wa, (amax - a0) / wa) * columns((bmin - b0) / wb, (bmax - b0) / wb);
      sum += box;
      counts.max = std::max(counts.max, box);
    }
    triangles += v.num_triangles;
  }
  counts.mean = triangles ? sum / triangles : 0;
  return counts;
}

Kernel automatic_column_kernel(const std::vector<CavityView>& cavities, const Frame& frame, int n) {
  // Leveraging when the mean candidate count a triangle is at most this and no triangle's box
  // holds more columns than the second.
  constexpr double kLeveragingMean = 4, kLeveragingMax = 64;
  // Fine meshes on coarse grids: most triangles cover no column or one, nothing needs
  // balancing, and the paper's kernel skips the binning and tiles that the tiled and fused
  // kernels pay for (docs/fluidweight.md, "When each kernel wins"). Only while no box is
  // large: leveraging's k comes from the mean, and a few large boxes among small ones would
  // each be walked by one thread. Otherwise tiled: with its kernels started overlapped it
  // is faster than the fused one on every case measured, small cavities included.
  const CandidateCounts c = candidate_counts(cavities, frame, n);
  return c.mean <= kLeveragingMean && c.max <= kLeveragingMax ? Kernel::leveraging : Kernel::tiled;
}

}  // namespace fluidweight::detail
