// The automatic kernel choice, from a batch's positions (device.cu, set_cavities).
#pragma once

#include <vector>

#include "../cpu.hpp"

namespace fluidweight::detail {

// Candidate columns a triangle's projected box holds, from positions (before the first call,
// for automatic's choice): the mean over all triangles of a batch and the largest.
struct CandidateCounts {
  double mean = 0;
  double max = 0;
};

CandidateCounts candidate_counts(const std::vector<CavityView>& cavities, const Frame& frame,
                                 int n);

// The column kernel that Kernel::automatic stands for with these positions.
Kernel automatic_column_kernel(const std::vector<CavityView>& cavities, const Frame& frame, int n);

}  // namespace fluidweight::detail
