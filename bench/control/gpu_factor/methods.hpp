// The factorizations compared (docs/control.md, "The factorization on a GPU"). Each runs
// the same protocol: pattern analysed once, then per repeat new values from the host,
// a numeric factorization and one solve whose right-hand side comes from and whose
// solution goes back to the host, as in a control step.
#pragma once

#include <string>
#include <vector>

#include "csr.hpp"

struct Protocol {
  const Csr* a;
  std::vector<std::vector<double>> sets;  // values per step, rotated
  std::vector<double> b;                  // right-hand side
  int repeats;
};

// Fill-reducing symmetric ordering q (metis, symamd or symrcm, cuSOLVER's host routines)
// and B = A(q, q): B's pattern and, per entry of B, the entry of A it takes.
struct Reordered {
  std::vector<int> q, row_start, column, map;
};
Reordered reorder(const Csr& a, const std::string& ordering);

// The protocol's repeats, each a factorization of the next set of values and one solve:
// their medians and the last solve's relative residual go into res. solution() gives the
// solve's result on the host (read after the timing).
template <class Factor, class Solve, class Solution>
void time_repeats(const Protocol& p, Factor factor, Solve solve, Solution solution, Result& res) {
  std::vector<double> tf, ts;
  for (int k = 0; k < p.repeats; ++k) {
    const auto& v = p.sets[k % p.sets.size()];
    double t = now_s();
    factor(v);
    tf.push_back(now_s() - t);
    t = now_s();
    solve();
    ts.push_back(now_s() - t);
    if (k == p.repeats - 1) res.relres = relative_residual(*p.a, v.data(), p.b, solution());
  }
  res.factor_ms = 1e3 * median(tf);
  res.solve_ms = 1e3 * median(ts);
}

Result run_csrchol(const Protocol& p, const std::string& ordering);
Result run_rf(const Protocol& p, const std::string& ordering, int factor_alg, int solve_alg);
Result run_eigen(const Protocol& p, bool ldlt);
double upload_ms(const Protocol& p);
