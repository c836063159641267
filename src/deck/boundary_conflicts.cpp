#include "deck/boundary_conflicts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/deck_reader.hpp"
#include "common/error.hpp"

namespace hs {
namespace {

double prescribed(const DirichletConfig& bc, int d, const double* X, double s,
                  const ExactValue& exact) {
  if (bc.exact) return exact({X[0], X[1], X[2]}, s)[d];
  return bc.value[d] * (bc.scaled ? s : 1.0);
}

// Whether two entries prescribe component d of the node at X differently. Two values differ
// when they are not equal or one of them is ramped and the other not (0 is 0 either way). An
// exact solution's value is compared with a value at half and full load, to round-off of the
// body's size: a symmetry plane and an exact solution that is symmetric agree there.
bool differ(const DirichletConfig& a, const DirichletConfig& b, int d, const double* X,
            const ExactValue& exact, double size) {
  if (a.exact && b.exact) return false;
  if (!a.exact && !b.exact)
    return a.value[d] != b.value[d] || (a.scaled != b.scaled && a.value[d] != 0);
  for (const double s : {0.5, 1.0}) {
    const double pa = prescribed(a, d, X, s, exact), pb = prescribed(b, d, X, s, exact);
    if (!(std::abs(pa - pb) <= 1e-9 * std::max(std::abs(pa), std::abs(pb)) + 1e-12 * size))
      return true;
  }
  return false;
}

// "x = 0.03 m, z = 0 m at once (scaled: false)" for the components in `mask`.
std::string values(const DirichletConfig& bc, int mask) {
  std::vector<std::string> parts;
  for (int d = 0; d < 3; ++d) {
    if (!(mask & (1 << d))) continue;
    const std::string c(1, "xyz"[d]);
    if (bc.exact)
      parts.push_back(c + " from the exact solution");
    else
      parts.push_back(c + " = " + format_number(bc.value[d]) + " m" +
                      (bc.scaled ? "" : " at once (scaled: false)"));
  }
  return join(parts);
}

}  // namespace

template <class Index>
void check_boundary_conflicts(const Config& config,
                              const std::map<std::string, std::vector<Index>>& groups,
                              const std::vector<double>& x, int64_t owned, const ExactValue& exact,
                              MPI_Comm comm) {
  const auto& bcs = config.dirichlet;
  const int64_t m = static_cast<int64_t>(bcs.size());
  if (m < 2) return;
  const size_t nodes = x.size() / 3;
  bool any_exact = false;
  for (const auto& bc : bcs) any_exact |= bc.exact;
  if (any_exact && !exact)
    throw InputError(config.deck_path +
                     ": boundary: an entry asks for exact values but the deck "
                     "has no exact solution");
  // The body's size: the scale of round-off for an exact solution's values.
  double size = 0;
  if (any_exact) {
    const double inf = std::numeric_limits<double>::infinity();
    double box[6] = {inf, inf, inf, inf, inf, inf};  // min x, y, z; -max x, y, z
    for (size_t n = 0; n < nodes; ++n)
      for (int d = 0; d < 3; ++d) {
        box[d] = std::min(box[d], x[3 * n + d]);
        box[3 + d] = std::min(box[3 + d], -x[3 * n + d]);
      }
    MPI_Allreduce(MPI_IN_PLACE, box, 6, MPI_DOUBLE, MPI_MIN, comm);
    for (int d = 0; d < 3; ++d) size = std::max(size, -box[3 + d] - box[d]);
  }

  // Each node's component against the first entry that prescribes it; the first conflicting
  // pair (j, i), j < i, in the order of the deck, found wherever its nodes lie.
  std::vector<int> first(3 * nodes, -1);
  int64_t pair = std::numeric_limits<int64_t>::max();
  for (int64_t i = 0; i < m; ++i) {
    const auto it = groups.find(bcs[i].group);
    if (it == groups.end()) continue;
    for (const Index n : it->second)
      for (int d = 0; d < 3; ++d) {
        if (!bcs[i].components[d]) continue;
        int& f = first[3 * n + d];
        if (f < 0)
          f = static_cast<int>(i);
        else if (differ(bcs[f], bcs[i], d, &x[3 * n], exact, size))
          pair = std::min(pair, f * m + i);
      }
  }
  MPI_Allreduce(MPI_IN_PLACE, &pair, 1, MPI_INT64_T, MPI_MIN, comm);
  if (pair == std::numeric_limits<int64_t>::max()) return;
  const int64_t j = pair / m, i = pair % m;

  // The pair's nodes (each counted by its own rank), the components where they disagree, and
  // the node of smallest coordinates (x, then y, then z) to name one.
  std::vector<char> in_j(nodes, 0);
  if (const auto it = groups.find(bcs[j].group); it != groups.end())
    for (const Index n : it->second) in_j[n] = 1;
  int64_t count = 0;
  int mask = 0;
  std::array<double, 4> one = {0, 0, 0, 0};  // found, x, y, z
  if (const auto it = groups.find(bcs[i].group); it != groups.end())
    for (const Index n : it->second) {
      if (static_cast<int64_t>(n) >= owned || !in_j[n]) continue;
      int here = 0;
      for (int d = 0; d < 3; ++d)
        if (bcs[i].components[d] && bcs[j].components[d] &&
            differ(bcs[j], bcs[i], d, &x[3 * n], exact, size))
          here |= 1 << d;
      if (!here) continue;
      ++count;
      mask |= here;
      const std::array<double, 4> p = {1, x[3 * n], x[3 * n + 1], x[3 * n + 2]};
      if (one[0] == 0 ||
          std::lexicographical_compare(p.begin() + 1, p.end(), one.begin() + 1, one.end()))
        one = p;
    }
  MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_INT64_T, MPI_SUM, comm);
  MPI_Allreduce(MPI_IN_PLACE, &mask, 1, MPI_INT, MPI_BOR, comm);
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  std::vector<double> all(4 * ranks);
  MPI_Allgather(one.data(), 4, MPI_DOUBLE, all.data(), 4, MPI_DOUBLE, comm);
  for (int r = 0; r < ranks; ++r) {
    const double* p = &all[4 * r];
    if (p[0] != 0 &&
        (one[0] == 0 || std::lexicographical_compare(p + 1, p + 4, one.begin() + 1, one.end())))
      std::copy(p, p + 4, one.begin());
  }
  throw InputError(printable(
      config.deck_path + ": " + item_key("boundary", i) + ": group '" + bcs[i].group +
      "' prescribes " + values(bcs[i], mask) + " on " + std::to_string(count) +
      (count == 1 ? " node" : " nodes") + " that " + item_key("boundary", j) + " (group '" +
      bcs[j].group + "') prescribes " + values(bcs[j], mask) + " (one at (" +
      format_number(one[1]) + ", " + format_number(one[2]) + ", " + format_number(one[3]) +
      ")); a component of a node takes one condition: give both the same value, or leave the "
      "shared nodes out of one of the groups"));
}

template void check_boundary_conflicts(const Config&,
                                       const std::map<std::string, std::vector<int32_t>>&,
                                       const std::vector<double>&, int64_t, const ExactValue&,
                                       MPI_Comm);
template void check_boundary_conflicts(const Config&,
                                       const std::map<std::string, std::vector<int64_t>>&,
                                       const std::vector<double>&, int64_t, const ExactValue&,
                                       MPI_Comm);

}  // namespace hs
