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

Result run_csrchol(const Protocol& p, const std::string& ordering);
Result run_rf(const Protocol& p, const std::string& ordering, int factor_alg, int solve_alg);
Result run_eigen(const Protocol& p, bool ldlt);
double upload_ms(const Protocol& p);
