// The liquid's weight on the walls of a closed cavity, by the column method of the seed paper
// (Section III, Steps 1-5, Algorithm 1) on the CPU and with CUDA, or by the closed-form
// hydrostatic pressure. docs/fluidweight.md explains the method, the fill rule and the kernels.
//
// This module builds on its own (cmake -S cuda) with a C++17 compiler; its CUDA part is built
// when the CUDA toolkit is found. It depends on nothing else of hydrosoft.
#pragma once

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace fluidweight {

// Bad input: an open, non-manifold or inconsistently oriented mesh, an unreadable file, an
// invalid option. The message names the file, the element or the option, and the reason.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// CUDA was asked for but is not built in, there is no device, or a CUDA call failed.
struct DeviceError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A closed triangle surface: 3 coordinates a vertex, 3 vertex indices a triangle. Triangles may
// be oriented outward or inward, consistently over the surface.
struct SurfaceMesh {
  std::vector<double> vertices;
  std::vector<int> triangles;
  int num_vertices() const { return static_cast<int>(vertices.size() / 3); }
  int num_triangles() const { return static_cast<int>(triangles.size() / 3); }
};

// column: the paper's column method, each section's weight on its floor. column_head: the
// same columns, each floor and ceiling loaded by the liquid's pressure at its depth below the
// highest point (the head above a section's ceiling pushes its floor down and its ceiling up:
// zero net, but it inflates). hydrostatic: that pressure on every wall, in closed
// form (docs/fluidweight.md, "The head above a section").
enum class Method { column, column_head, hydrostatic };
enum class Implementation { cpu_reference, cpu_fast, cuda };
// CUDA kernels for Steps 3-4 (see docs/fluidweight.md): the paper's leveraging kernel, one
// thread per triangle, tiles with a load-balanced search inside each tile, Steps 1-5 fused in
// one launch (small cavities), or automatic: leveraging for fine meshes on coarse grids, else
// tiled.
enum class Kernel { leveraging, triangle_parallel, tiled, fused, automatic };
enum class Precision { float32, float64 };
// cpu_fast: the instruction set of its kernels, capped at what the processor has: the widest
// (AVX-512, else AVX2, else portable), at most AVX2, or portable C++. All cover the same
// columns; heights differ in rounding only, so `portable` gives the same bits on every processor.
enum class CpuKernels { widest, avx2, portable };

struct Options {
  Method method = Method::column;
  Implementation implementation = Implementation::cpu_fast;
  Kernel kernel = Kernel::tiled;             // CUDA only
  Precision precision = Precision::float64;  // CUDA only; the CPU paths compute in double
  int grid = 200;                            // N: N x N columns over the projected box
  double rho = 1.0;                          // density of the liquid
  std::array<double, 3> gravity{0.0, -1.0, 0.0};
  double alpha = 0.25;  // leveraging: k = max(1, floor(alpha c)) threads
  int threads = 0;      // cpu_fast: worker threads; 0 = all hardware ones (one for small problems)
  CpuKernels cpu_kernels = CpuKernels::widest;  // cpu_fast
  int tile = 0;  // tiled and fused: tile edge in columns (8 or 16), 0 = auto
};

struct Timings {
  double wall_ms = 0.0;  // the whole call on the host clock (transfers included for CUDA)
  double gpu_ms = -1.0;  // CUDA: the call's kernels, timed with CUDA events; -1 on the CPU
};

struct Result {
  std::vector<double> forces;       // 3 per vertex, in input order
  double column_volume = 0.0;       // sum of the column sections; hydrostatic: |signed volume|
  double signed_volume = 0.0;       // divergence theorem; negative for an inward orientation
  double total_weight = 0.0;        // |sum of the nodal forces|
  long long unmatched_columns = 0;  // columns whose floors and ceilings do not pair (0 when closed)
  // Column methods: rho |g| times one column's cross-section times the cavity's height, the
  // most one column section weighs: a wall crossing a column's centre moves up to this much
  // force between its nodes, so the weights jump by it. 0 for the closed form.
  double column_weight = 0.0;
  Timings timings;
};

// Throws InputError naming the first bad edge unless every edge is shared by exactly two
// triangles that use it in opposite directions (closed, manifold, consistently oriented).
// `name` (a file name, say) starts the message.
void check_closed_surface(const SurfaceMesh& mesh, const std::string& name = "mesh");

// Keeps the cavities' connectivity, checked once, and (for CUDA) the device buffers and the
// captured CUDA graph between calls: a control loop creates one and calls compute() every step.
class Context {
 public:
  explicit Context(const Options& options);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Checks each cavity (check_closed_surface) and keeps its connectivity and positions.
  void set_cavities(const std::vector<SurfaceMesh>& cavities);
  // New positions, one array of 3 * num_vertices doubles per cavity, same connectivity. The
  // arrays are read by compute(), not copied here: they must live until then.
  void set_positions(const std::vector<const double*>& positions);
  // Forces for the current positions, one Result per cavity.
  const std::vector<Result>& compute();

  // CUDA only: replays the captured graph of the last compute() `repeats` times, each between
  // two CUDA events, and returns the milliseconds of each replay.
  std::vector<double> time_device_replays(int repeats);

  const Options& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-shot conveniences (a Context made and dropped).
Result compute(const SurfaceMesh& mesh, const Options& options);
std::vector<Result> compute_batch(const std::vector<SurfaceMesh>& cavities, const Options& options);

// True when the CUDA part is built in and a device is present.
bool cuda_available();
// The CUDA device's name and multiprocessor count, or "" without one.
std::string cuda_device_name();

// Names used by the command line and the JSON output.
std::string to_string(Method method);
std::string to_string(Kernel kernel);
std::string to_string(Precision precision);
std::string to_string(Implementation implementation);
Method parse_method(const std::string& name);
Kernel parse_kernel(const std::string& name);
Precision parse_precision(const std::string& name);

}  // namespace fluidweight
