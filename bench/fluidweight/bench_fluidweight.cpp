// Benchmark of the fluid-weight module in the layout of the seed paper's Table I, plus the
// batched four-cavity case, kernels on even and uneven meshes, the leveraging kernel's alpha,
// and the error of the nodal distribution against run time. Results go to stdout as markdown
// tables and, with --out, as one JSON object a line. Timing: CPU calls on the host clock
// (median of the repeats); GPU: CUDA events around replays of the captured CUDA graph of one
// call (median of 50 replays, after two warm-up calls), and the whole call with its transfers.
//
//   bench_fluidweight [--meshes DIR] [--out FILE] [--quick] [--targets] [--fused]
// --targets: the cases only; --fused: the tiled and fused kernels (and automatic's
// choice) side by side on small and large meshes.
// DIR holds armadillo.obj and the other meshes of docs/fluidweight.md (skipped when absent).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <thread>
#include <vector>

#ifdef __linux__
#include <sched.h>
#endif

#include "fluidweight/fluidweight.hpp"
#include "fluidweight/mesh_io.hpp"
#include "fluidweight/shapes.hpp"

namespace fw = fluidweight;

namespace {

std::ofstream json;
bool quick = false;
bool only_targets = false;  // --targets: the cases only
bool only_fused = false;    // --fused: tiled against fused

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n == 0 ? NAN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void record(const std::string& fields) {
  if (json) json << "{" << fields << "}\n" << std::flush;
}

std::string kv(const std::string& k, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "\"%s\": %.10g", k.c_str(), v);
  return buf;
}
std::string kv(const std::string& k, const std::string& v) {
  return "\"" + k + "\": \"" + v + "\"";
}

fw::Options base(int n) {
  fw::Options o;
  o.grid = n;
  o.rho = 1.0;
  o.gravity = {0, -1, 0};
  return o;
}

struct Timed {
  std::vector<fw::Result> results;
  double ms = NAN;       // CPU: median call; GPU: median graph replay
  double call_ms = NAN;  // GPU: median whole call (upload, graph, download)
};

// One-thread CPU figures are taken on one core: the calling thread (the fast path's only
// worker with one thread) is pinned to the last core for the call and then released.
struct PinToLastCore {
#ifdef __linux__
  cpu_set_t before;
  bool pinned = false;
  explicit PinToLastCore(bool on) {
    const int cores = static_cast<int>(std::thread::hardware_concurrency());
    if (!on || cores < 2 || sched_getaffinity(0, sizeof before, &before) != 0) return;
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cores - 1, &one);
    pinned = sched_setaffinity(0, sizeof one, &one) == 0;
  }
  ~PinToLastCore() {
    if (pinned) sched_setaffinity(0, sizeof before, &before);
  }
#else
  explicit PinToLastCore(bool) {}
#endif
};

Timed time_cpu(const std::vector<fw::SurfaceMesh>& cavities, int n, int threads,
               fw::Method method = fw::Method::column) {
  PinToLastCore pin(threads == 1);
  fw::Options o = base(n);
  o.implementation = fw::Implementation::cpu_fast;
  o.threads = threads;
  o.method = method;
  fw::Context context(o);
  context.set_cavities(cavities);
  Timed t;
  std::vector<double> ms;
  int repeats = quick ? 2 : 7;
  for (int r = 0; r < repeats; ++r) {
    t.results = context.compute();
    ms.push_back(t.results.front().timings.wall_ms);
  }
  t.ms = median(ms);
  return t;
}

Timed time_gpu(const std::vector<fw::SurfaceMesh>& cavities, int n, fw::Kernel kernel,
               fw::Precision precision, double alpha = 0.25,
               fw::Method method = fw::Method::column) {
  fw::Options o = base(n);
  o.implementation = fw::Implementation::cuda;
  o.kernel = kernel;
  o.precision = precision;
  o.alpha = alpha;
  o.method = method;
  fw::Context context(o);
  context.set_cavities(cavities);
  Timed t;
  std::vector<double> calls;
  for (int r = 0; r < (quick ? 3 : 7); ++r) {
    t.results = context.compute();
    if (r >= 2) calls.push_back(t.results.front().timings.wall_ms);
  }
  t.call_ms = median(calls);
  t.ms = median(context.time_device_replays(quick ? 10 : 50));
  return t;
}

double relative_force_error(const fw::Result& a, const fw::Result& ref) {
  double d = 0, s = 0;
  for (size_t k = 0; k < ref.forces.size(); ++k) {
    d += (a.forces[k] - ref.forces[k]) * (a.forces[k] - ref.forces[k]);
    s += ref.forces[k] * ref.forces[k];
  }
  return std::sqrt(d / s);
}

const std::vector<std::pair<fw::Kernel, fw::Precision>> kVariants = {
    {fw::Kernel::leveraging, fw::Precision::float32},
    {fw::Kernel::leveraging, fw::Precision::float64},
    {fw::Kernel::triangle_parallel, fw::Precision::float32},
    {fw::Kernel::triangle_parallel, fw::Precision::float64},
    {fw::Kernel::tiled, fw::Precision::float32},
    {fw::Kernel::tiled, fw::Precision::float64}};

std::string short_name(fw::Kernel k, fw::Precision p) {
  std::string n = k == fw::Kernel::leveraging          ? "lev"
                  : k == fw::Kernel::triangle_parallel ? "tri"
                                                       : fw::to_string(k);
  return n + (p == fw::Precision::float32 ? " f32" : " f64");
}

// Table I: column volume, its error, CPU ms on 1 and all threads, GPU us for every kernel.
void table_one(const std::string& label, const fw::SurfaceMesh& mesh, bool gpu, int threads) {
  std::printf("\n### %s (%d triangles)\n\n", label.c_str(), mesh.num_triangles());
  std::printf("| grid | column volume | rel. error vs signed | CPU 1 thr ms | CPU %d thr ms |",
              threads);
  if (gpu) {
    for (auto [k, p] : kVariants) std::printf(" %s us |", short_name(k, p).c_str());
    std::printf(" call ms (tiled f32) |");
  }
  std::printf("\n|---|---|---|---|---|%s\n", gpu ? "---|---|---|---|---|---|---|" : "");
  std::vector<int> grids = {30, 50, 100, 200, 500, 1000, 1500};
  if (quick) grids = {30, 200, 1000};
  for (int n : grids) {
    Timed one = time_cpu({mesh}, n, 1), all = time_cpu({mesh}, n, threads);
    const fw::Result& r = one.results.front();
    double error = (r.column_volume - std::fabs(r.signed_volume)) / std::fabs(r.signed_volume);
    std::printf("| %d^2 | %.6f | %.2e | %.2f | %.2f |", n, r.column_volume, error, one.ms, all.ms);
    std::string fields = kv("table", "I") + ", " + kv("mesh", label) + ", " + kv("grid", n) + ", " +
                         kv("volume", r.column_volume) + ", " +
                         kv("signed_volume", r.signed_volume) + ", " + kv("cpu1_ms", one.ms) +
                         ", " + kv("cpu_all_ms", all.ms);
    if (gpu) {
      double call = NAN;
      for (auto [k, p] : kVariants) {
        Timed g = time_gpu({mesh}, n, k, p);
        std::printf(" %.1f |", 1000 * g.ms);
        fields += ", " + kv(short_name(k, p) + " us", 1000 * g.ms);
        if (k == fw::Kernel::tiled && p == fw::Precision::float32) call = g.call_ms;
        if (std::fabs(g.results.front().column_volume - r.column_volume) > 1e-5 * r.column_volume) {
          std::printf(" (volume %.7f!) |", g.results.front().column_volume);
        }
      }
      std::printf(" %.3f |", call);
      fields += ", " + kv("call_ms", call);
    }
    std::printf("\n");
    std::fflush(stdout);
    record(fields);
  }
}

void batched(const std::string& label, const std::vector<fw::SurfaceMesh>& cavities, bool gpu,
             int threads) {
  int total = 0;
  for (const auto& c : cavities) total += c.num_triangles();
  Timed one = time_cpu(cavities, 200, 1), all = time_cpu(cavities, 200, threads);
  std::printf("| %s (%d triangles) | %.2f | %.2f |", label.c_str(), total, one.ms, all.ms);
  std::string fields = kv("table", "batch") + ", " + kv("mesh", label) + ", " +
                       kv("cpu1_ms", one.ms) + ", " + kv("cpu_all_ms", all.ms);
  if (gpu) {
    for (auto [k, p] : kVariants) {
      Timed g = time_gpu(cavities, 200, k, p);
      std::printf(" %.1f |", 1000 * g.ms);
      fields += ", " + kv(short_name(k, p) + " us", 1000 * g.ms);
    }
  }
  std::printf("\n");
  record(fields);
}

void kernels_on_meshes(const std::vector<std::pair<std::string, fw::SurfaceMesh>>& meshes) {
  std::printf("\n### Kernels on even and uneven meshes (GPU us, graph replay)\n\n");
  std::printf("| mesh | triangles | grid |");
  for (auto [k, p] : kVariants) std::printf(" %s |", short_name(k, p).c_str());
  std::printf("\n|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& [label, mesh] : meshes) {
    for (int n : {200, 1000}) {
      std::printf("| %s | %d | %d^2 |", label.c_str(), mesh.num_triangles(), n);
      std::string fields = kv("table", "kernels") + ", " + kv("mesh", label) + ", " + kv("grid", n);
      for (auto [k, p] : kVariants) {
        Timed g = time_gpu({mesh}, n, k, p);
        std::printf(" %.1f |", 1000 * g.ms);
        fields += ", " + kv(short_name(k, p) + " us", 1000 * g.ms);
      }
      std::printf("\n");
      std::fflush(stdout);
      record(fields);
    }
  }
}

void alpha_sweep(const std::string& label, const fw::SurfaceMesh& mesh) {
  std::printf("\n### Leveraging kernel's alpha, %s, f32 (GPU us)\n\n| grid |", label.c_str());
  const std::vector<double> alphas = {0.0625, 0.125, 0.25, 0.5, 1.0, 2.0};
  for (double a : alphas) std::printf(" alpha %.4g |", a);
  std::printf("\n|---|---|---|---|---|---|---|\n");
  for (int n : {200, 1000}) {
    std::printf("| %d^2 |", n);
    std::string fields = kv("table", "alpha") + ", " + kv("mesh", label) + ", " + kv("grid", n);
    for (double a : alphas) {
      Timed g = time_gpu({mesh}, n, fw::Kernel::leveraging, fw::Precision::float32, a);
      std::printf(" %.1f |", 1000 * g.ms);
      fields += ", " + kv("alpha " + std::to_string(a), 1000 * g.ms);
    }
    std::printf("\n");
    record(fields);
  }
}

// Error of the nodal forces against a much finer grid, with what each grid costs.
void error_against_time(const std::string& label, const fw::SurfaceMesh& mesh, bool gpu,
                        int threads) {
  const int finest = gpu ? 4000 : 2000;
  fw::Options o = base(finest);
  o.implementation = gpu ? fw::Implementation::cuda : fw::Implementation::cpu_fast;
  o.kernel = fw::Kernel::tiled;
  o.precision = fw::Precision::float64;
  fw::Result reference = fw::compute(mesh, o);
  std::printf("\n### Nodal distribution error vs %d^2, %s\n\n", finest, label.c_str());
  std::printf("| grid | rel. L2 error of nodal forces | CPU 1 thr ms | CPU %d thr ms |%s\n",
              threads, gpu ? " GPU tiled f32 us | GPU tiled f64 us |" : "");
  std::printf("|---|---|---|---|%s\n", gpu ? "---|---|" : "");
  std::vector<int> grids = {30, 50, 100, 200, 300, 500, 700, 1000, 1500, 2000};
  if (quick) grids = {30, 200, 1000};
  for (int n : grids) {
    Timed one = time_cpu({mesh}, n, 1), all = time_cpu({mesh}, n, threads);
    double error = relative_force_error(one.results.front(), reference);
    std::printf("| %d^2 | %.3e | %.2f | %.2f |", n, error, one.ms, all.ms);
    std::string fields = kv("table", "error") + ", " + kv("mesh", label) + ", " + kv("grid", n) +
                         ", " + kv("force_error", error) + ", " + kv("cpu1_ms", one.ms) + ", " +
                         kv("cpu_all_ms", all.ms);
    if (gpu) {
      Timed f32 = time_gpu({mesh}, n, fw::Kernel::tiled, fw::Precision::float32);
      Timed f64 = time_gpu({mesh}, n, fw::Kernel::tiled, fw::Precision::float64);
      std::printf(" %.1f | %.1f |", 1000 * f32.ms, 1000 * f64.ms);
      fields += ", " + kv("tiled f32 us", 1000 * f32.ms) + ", " + kv("tiled f64 us", 1000 * f64.ms);
    }
    std::printf("\n");
    std::fflush(stdout);
    record(fields);
  }
}

void hydrostatic_times(const std::vector<std::pair<std::string, fw::SurfaceMesh>>& meshes, bool gpu,
                       int threads) {
  std::printf(
      "\n### Closed-form hydrostatic load\n\n| mesh | CPU 1 thr ms | GPU f32 us | GPU f64 us "
      "|\n|---|---|---|---|\n");
  for (const auto& [label, mesh] : meshes) {
    Timed cpu = time_cpu({mesh}, 1, 1, fw::Method::hydrostatic);
    std::printf("| %s | %.3f |", label.c_str(), cpu.ms);
    std::string fields =
        kv("table", "hydrostatic") + ", " + kv("mesh", label) + ", " + kv("cpu1_ms", cpu.ms);
    if (gpu) {
      for (fw::Precision p : {fw::Precision::float32, fw::Precision::float64}) {
        Timed g = time_gpu({mesh}, 1, fw::Kernel::tiled, p, 0.25, fw::Method::hydrostatic);
        std::printf(" %.1f |", 1000 * g.ms);
        fields += ", " + kv(fw::to_string(p) + " us", 1000 * g.ms);
      }
    }
    std::printf("\n");
    record(fields);
    (void)threads;
  }
}

std::string cpu_name() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown CPU";
}

fw::SurfaceMesh rotated_copy(const fw::SurfaceMesh& m, double angle, double shift) {
  fw::SurfaceMesh r = m;
  double c = std::cos(angle), s = std::sin(angle);
  for (size_t v = 0; v < r.vertices.size(); v += 3) {
    double x = m.vertices[v], z = m.vertices[v + 2];
    r.vertices[v] = c * x - s * z + shift;
    r.vertices[v + 2] = s * x + c * z;
  }
  return r;
}

// The targets only (--targets): tiled f32/f64 graph replays for the armadillo at
// 1000^2 and 1500^2, the sphere at 200^2, four spheres at 200^2 batched; the CPU fast path on
// one thread for the armadillo at 1000^2. Each GPU figure is timed twice (two contexts) so that
// the spread shows.
void targets(const std::map<std::string, fw::SurfaceMesh>& files, const fw::SurfaceMesh& sphere,
             bool gpu) {
  std::vector<std::pair<std::string, std::pair<std::vector<fw::SurfaceMesh>, int>>> cases;
  if (files.count("armadillo.obj")) {
    cases.push_back({"armadillo 1000^2", {{files.at("armadillo.obj")}, 1000}});
    cases.push_back({"armadillo 1500^2", {{files.at("armadillo.obj")}, 1500}});
    cases.push_back({"armadillo 200^2", {{files.at("armadillo.obj")}, 200}});
  }
  cases.push_back({"sphere 200^2", {{sphere}, 200}});
  cases.push_back({"sphere 1000^2", {{sphere}, 1000}});
  std::vector<fw::SurfaceMesh> spheres;
  for (int c = 0; c < 4; ++c) spheres.push_back(rotated_copy(sphere, 0.3 * c, 3.0 * c));
  cases.push_back({"4 spheres 200^2", {spheres, 200}});
  std::printf(
      "\n### Targets\n\n| case | kernel | us (run 1) | us (run 2) | volume | unmatched |\n"
      "|---|---|---|---|---|---|\n");
  for (auto& [name, c] : cases) {
    if (!gpu) break;
    for (auto k : {fw::Kernel::tiled, fw::Kernel::fused}) {
      for (auto p : {fw::Precision::float32, fw::Precision::float64}) {
        Timed a, b;
        try {
          a = time_gpu(c.first, c.second, k, p);
          b = time_gpu(c.first, c.second, k, p);
        } catch (const fw::DeviceError& e) {
          std::printf("| %s | %s | - | - | (%s) | |\n", name.c_str(), short_name(k, p).c_str(),
                      e.what());
          continue;
        }
        long long unmatched = 0;
        for (auto& r : a.results) unmatched += r.unmatched_columns;
        std::printf("| %s | %s | %.1f | %.1f | %.9g | %lld |\n", name.c_str(),
                    short_name(k, p).c_str(), 1000 * a.ms, 1000 * b.ms,
                    a.results.front().column_volume, unmatched);
        record(kv("targets", name) + ", " + kv("kernel", short_name(k, p)) + ", " +
               kv("us", 1000 * a.ms) + ", " + kv("us2", 1000 * b.ms) + ", " +
               kv("volume", a.results.front().column_volume));
        std::fflush(stdout);
      }
    }
  }
  if (files.count("armadillo.obj")) {
    for (int n : {200, 1000}) {
      Timed t = time_cpu({files.at("armadillo.obj")}, n, 1);
      std::printf("| armadillo %d^2 | CPU 1 thread | %.2f ms | | %.9g | %lld |\n", n, t.ms,
                  t.results.front().column_volume, t.results.front().unmatched_columns);
      record(kv("targets", "armadillo cpu1 " + std::to_string(n)) + ", " + kv("ms", t.ms));
    }
  }
}

// The tiled and fused kernels side by side (and the automatic choice, f32), graph replays.
void fused_comparison(const std::map<std::string, fw::SurfaceMesh>& files,
                      const fw::SurfaceMesh& sphere) {
  std::vector<std::pair<std::string, std::vector<fw::SurfaceMesh>>> cases = {
      {"sphere", {sphere}},
      {"uneven sphere (5, 20)", {fw::shapes::uneven_sphere(5, 20.0)}},
      {"sphere level 5", {fw::shapes::icosphere(5)}}};
  std::vector<fw::SurfaceMesh> spheres;
  for (int c = 0; c < 4; ++c) spheres.push_back(rotated_copy(sphere, 0.3 * c, 3.0 * c));
  cases.push_back({"4 spheres", spheres});
  for (const char* name : {"tray_bottom.stl", "fertility.off", "armadillo.obj"}) {
    if (files.count(name)) cases.push_back({name, {files.at(name)}});
  }
  std::printf(
      "\n### Tiled against fused (GPU us, graph replay)\n\n| mesh | grid | tiled f32 | "
      "fused f32 | tiled f64 | fused f64 | automatic f32 |\n|---|---|---|---|---|---|---|\n");
  std::vector<int> grids = {30, 100, 200, 500, 1000};
  if (quick) grids = {200, 1000};
  for (const auto& [label, cavities] : cases) {
    for (int n : grids) {
      std::printf("| %s | %d^2 |", label.c_str(), n);
      std::string fields = kv("table", "fused") + ", " + kv("mesh", label) + ", " + kv("grid", n);
      for (auto [k, p] : std::vector<std::pair<fw::Kernel, fw::Precision>>{
               {fw::Kernel::tiled, fw::Precision::float32},
               {fw::Kernel::fused, fw::Precision::float32},
               {fw::Kernel::tiled, fw::Precision::float64},
               {fw::Kernel::fused, fw::Precision::float64},
               {fw::Kernel::automatic, fw::Precision::float32}}) {
        try {
          Timed g = time_gpu(cavities, n, k, p);
          std::printf(" %.1f |", 1000 * g.ms);
          fields += ", " + kv(short_name(k, p) + " us", 1000 * g.ms);
        } catch (const fw::DeviceError&) {
          std::printf(" - |");
        }
      }
      std::printf("\n");
      std::fflush(stdout);
      record(fields);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string dir, out;
  for (int k = 1; k < argc; ++k) {
    std::string a = argv[k];
    if (a == "--meshes" && k + 1 < argc)
      dir = argv[++k];
    else if (a == "--out" && k + 1 < argc)
      out = argv[++k];
    else if (a == "--quick")
      quick = true;
    else if (a == "--targets")
      only_targets = true;
    else if (a == "--fused")
      only_fused = true;
    else {
      std::fprintf(
          stderr,
          "usage: bench_fluidweight [--meshes DIR] [--out FILE] [--quick] [--targets] [--fused]\n");
      return 2;
    }
  }
  if (!out.empty()) json.open(out);
  const bool gpu = fw::cuda_available();
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::printf("CPU: %s, %d hardware threads\nGPU: %s\n", cpu_name().c_str(), threads,
              gpu ? fw::cuda_device_name().c_str() : "none");
  record(kv("cpu", cpu_name()) + ", " + kv("threads", threads) + ", " +
         kv("gpu", gpu ? fw::cuda_device_name() : "none"));

  std::map<std::string, fw::SurfaceMesh> files;
  for (const char* name : {"armadillo.obj", "tray_bottom.stl", "sword.obj", "fertility.off"}) {
    std::string path = dir + "/" + name;
    if (!dir.empty() && std::ifstream(path)) files[name] = fw::read_surface(path);
  }
  const fw::SurfaceMesh sphere = fw::shapes::icosphere(4);
  if (only_targets) {
    targets(files, sphere, gpu);
    return 0;
  }
  if (only_fused) {
    if (gpu) fused_comparison(files, sphere);
    return 0;
  }
  table_one("sphere, radius 1", sphere, gpu, threads);
  if (files.count("armadillo.obj")) table_one("armadillo", files["armadillo.obj"], gpu, threads);

  std::printf(
      "\n### Four cavities at 200^2, one batched call\n\n| cavities | CPU 1 thr ms | CPU %d thr ms "
      "|",
      threads);
  if (gpu) {
    for (auto [k, p] : kVariants) std::printf(" %s us |", short_name(k, p).c_str());
  }
  std::printf("\n|---|---|---|%s\n", gpu ? "---|---|---|---|---|---|" : "");
  std::vector<fw::SurfaceMesh> spheres;
  for (int c = 0; c < 4; ++c) spheres.push_back(rotated_copy(sphere, 0.3 * c, 3.0 * c));
  batched("4 spheres", spheres, gpu, threads);
  if (files.count("armadillo.obj")) {
    std::vector<fw::SurfaceMesh> armadillos;
    for (int c = 0; c < 4; ++c)
      armadillos.push_back(rotated_copy(files["armadillo.obj"], 0.3 * c, 2.0 * c));
    batched("4 armadillos", armadillos, gpu, threads);
  }

  if (gpu) {
    std::vector<std::pair<std::string, fw::SurfaceMesh>> meshes = {
        {"sphere (even)", sphere},
        {"uneven sphere (areas 1:10^5)", fw::shapes::uneven_sphere(5, 20.0)}};
    for (const char* name : {"armadillo.obj", "tray_bottom.stl", "sword.obj", "fertility.off"}) {
      if (files.count(name)) meshes.emplace_back(name, files[name]);
    }
    if (!quick) kernels_on_meshes(meshes);
    if (!quick) alpha_sweep("sphere", sphere);
    if (!quick && files.count("armadillo.obj")) alpha_sweep("armadillo", files["armadillo.obj"]);
  }
  error_against_time("sphere", sphere, gpu, threads);
  if (files.count("armadillo.obj"))
    error_against_time("armadillo", files["armadillo.obj"], gpu, threads);
  std::vector<std::pair<std::string, fw::SurfaceMesh>> hydro = {{"sphere", sphere}};
  if (files.count("armadillo.obj")) hydro.emplace_back("armadillo", files["armadillo.obj"]);
  hydrostatic_times(hydro, gpu, threads);
  return 0;
}
