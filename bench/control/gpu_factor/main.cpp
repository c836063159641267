// Usage: gpu_factor K.bin [--repeats N] [--methods m1,m2,...]
// K.bin: a tangent written by hydrosoft with -ksp_view_mat binary:K.bin (bench_factor.cpp).
// Methods: chol:ORDERING (cuSOLVER csrchol), rf:ORDERING:FACTOR_ALG:SOLVE_ALG (cusolverRf),
// eigen:llt, eigen:ldlt (CPU); ORDERING is
// metis, symamd or symrcm. Prints one JSON line per method and a Markdown table last.
#include <cstdio>
#include <fstream>
#include <sstream>

#include "gpu.hpp"
#include "methods.hpp"

double upload_ms(const Protocol& p) {
  const size_t bytes = 8 * p.a->value.size();
  DeviceArray<double> d(p.a->value.size());
  std::vector<double> t;
  for (int k = 0; k < p.repeats; ++k) {
    double t0 = now_s();
    CUDA_CHECK(cudaMemcpy(d.p, p.sets[k % p.sets.size()].data(), bytes, cudaMemcpyHostToDevice));
    t.push_back(now_s() - t0);
  }
  return 1e3 * median(t);
}

namespace {

std::vector<std::string> split(const std::string& s, char c) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, c);) out.push_back(part);
  return out;
}

Result run_method(const Protocol& p, const std::string& spec) {
  auto f = split(spec, ':');
  if (f[0] == "chol") return run_csrchol(p, f.size() > 1 ? f[1] : "metis");
  if (f[0] == "rf")
    return run_rf(p, f.size() > 1 ? f[1] : "metis", f.size() > 2 ? std::stoi(f[2]) : 0,
                  f.size() > 3 ? std::stoi(f[3]) : 1);
  if (f[0] == "eigen") return run_eigen(p, f.size() > 1 && f[1] == "ldlt");
  throw std::runtime_error("unknown or not built: " + spec);
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "?";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: gpu_factor K.bin [--repeats N] [--methods m1,m2,...]\n");
    return 2;
  }
  int repeats = 21;
  std::string methods = "eigen:llt,chol:metis,chol:symamd,rf:metis:0:1,rf:metis:2:3";
  for (int i = 2; i + 1 < argc; i += 2) {
    std::string o = argv[i];
    if (o == "--repeats")
      repeats = std::stoi(argv[i + 1]);
    else if (o == "--methods")
      methods = argv[i + 1];
    else {
      std::fprintf(stderr, "unknown option %s\n", o.c_str());
      return 2;
    }
  }
  try {
    Csr a = read_petsc_binary(argv[1]);
    Protocol p{&a, perturbed_sets(a, 4), std::vector<double>(a.n), repeats};
    for (int i = 0; i < a.n; ++i) p.b[i] = std::sin(0.37 * i + 1.0);  // not special, not zero
    std::printf("# %s: n = %d, nnz = %d; CPU: %s\n", argv[1], a.n, a.nnz(), cpu_model().c_str());
    std::vector<Result> results;
    bool gpu = methods.find("chol") != std::string::npos || methods.find("rf") != std::string::npos;
    double up = NAN;
    if (gpu) {
      cudaDeviceProp prop;
      CUDA_CHECK(cudaGetDeviceProperties(&prop, 0));
      std::printf("# GPU: %s\n", prop.name);
      up = upload_ms(p);
    }
    for (const auto& spec : split(methods, ',')) {
      try {
        Result r = run_method(p, spec);
        r.upload_ms = spec.rfind("eigen", 0) == 0 ? NAN : up;
        std::printf(
            "{\"n\": %d, \"method\": \"%s\", \"setup_ms\": %.3f, \"factor_ms\": %.3f, "
            "\"upload_ms\": %.3f, \"solve_ms\": %.3f, \"relres\": %.2e, \"nnz_factor\": %.0f}\n",
            a.n, r.method.c_str(), r.setup_ms, r.factor_ms, r.upload_ms, r.solve_ms, r.relres,
            r.nnz_factor);
        std::fflush(stdout);
        results.push_back(r);
      } catch (const std::exception& e) {
        std::printf("# %s failed: %s\n", spec.c_str(), e.what());
        std::fflush(stdout);
      }
    }
    std::printf(
        "\n| n | method | setup (ms) | factor (ms) | of which values upload | solve (ms) | relres "
        "| nnz(factor) |\n|---|---|---|---|---|---|---|---|\n");
    for (const auto& r : results)
      std::printf("| %d | %s | %.1f | %.2f | %.2f | %.2f | %.1e | %.0f |\n", a.n, r.method.c_str(),
                  r.setup_ms, r.factor_ms, r.upload_ms, r.solve_ms, r.relres, r.nnz_factor);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gpu_factor: %s\n", e.what());
    return 1;
  }
  return 0;
}
