#include "reduction/design.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hs {
namespace {

// The first m primes, the Halton sequence's bases (their points stay uncorrelated in pairs).
std::vector<int> primes(int m) {
  std::vector<int> p;
  for (int c = 2; static_cast<int>(p.size()) < m; ++c) {
    bool prime = true;
    for (int d : p) prime &= c % d != 0;
    if (prime) p.push_back(c);
  }
  return p;
}

// i's digits in base b mirrored about the radix point: 0.d0 d1 d2... (b).
double radical_inverse(long long i, int b) {
  double scale = 1, value = 0;
  for (; i > 0; i /= b) {
    scale /= b;
    value += scale * static_cast<double>(i % b);
  }
  return value;
}

double distance2(const std::vector<double>& a, const std::vector<double>& b) {
  double d2 = 0;
  for (size_t i = 0; i < a.size(); ++i) d2 += (a[i] - b[i]) * (a[i] - b[i]);
  return d2;
}

}  // namespace

TrainingDesign grid_design(int m, int n) {
  TrainingDesign design;
  long long total = 1;
  for (int a = 0; a < m; ++a) total *= n;
  for (long long s = 0; s < total; ++s) {
    std::vector<int> index(m);
    long long rest = s;
    for (int a = 0; a < m; ++a) {
      index[a] = static_cast<int>(rest % n);
      rest /= n;
    }
    for (int a = m - 2; a >= 0; --a)  // serpentine: reverse where the higher index is odd
      if (index[a + 1] % 2 == 1) index[a] = n - 1 - index[a];
    std::vector<double> x(m);
    bool all_odd = true;
    for (int a = 0; a < m; ++a) {
      x[a] = static_cast<double>(index[a]) / (n - 1);
      all_odd &= index[a] % 2 == 1;
    }
    design.points.push_back(x);
    design.held_back.push_back(all_odd);
  }
  return design;
}

TrainingDesign halton_design(int m, int n, const std::vector<double>& start) {
  const long long corners = 1LL << m;
  if (m < 1 || m > 16 || n < corners + 4)
    throw std::invalid_argument("a Halton design of " + std::to_string(m) +
                                " actuators needs at least " + std::to_string(corners + 4) +
                                " samples (the 2^m corners and 4 more)");
  std::vector<std::vector<double>> points;
  std::vector<bool> held;
  for (long long c = 0; c < corners; ++c) {
    std::vector<double> x(m);
    for (int a = 0; a < m; ++a) x[a] = static_cast<double>((c >> a) & 1);
    points.push_back(x);
    held.push_back(false);
  }
  const std::vector<int> base = primes(m);
  for (long long i = 1; i <= n - corners; ++i) {
    std::vector<double> x(m);
    for (int a = 0; a < m; ++a) x[a] = radical_inverse(i, base[a]);
    points.push_back(x);
    held.push_back(i % 4 == 0);
  }
  // The walk: each solve starts from the equilibrium of the nearest point solved.
  TrainingDesign design;
  std::vector<bool> done(points.size(), false);
  std::vector<double> at = start;
  for (size_t k = 0; k < points.size(); ++k) {
    size_t next = 0;
    double best = std::numeric_limits<double>::infinity();
    for (size_t p = 0; p < points.size(); ++p)
      if (!done[p] && distance2(points[p], at) < best) {
        best = distance2(points[p], at);
        next = p;
      }
    done[next] = true;
    at = points[next];
    design.points.push_back(points[next]);
    design.held_back.push_back(held[next]);
  }
  return design;
}

}  // namespace hs
