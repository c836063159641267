// The CUDA backend: device buffers kept between calls, the call captured once as a CUDA graph
// and replayed, fixed-capacity buffers grown (and the graph recaptured) when a call reports an
// overflow.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>

#include "../device.hpp"
#include "device_common.cuh"

namespace fluidweight::detail {
namespace {

void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) {
    throw DeviceError(std::string("cuda: ") + what + ": " + cudaGetErrorString(status));
  }
}

// A device array that only grows.
template <typename T>
class DeviceArray {
 public:
  DeviceArray() = default;
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
  ~DeviceArray() { cudaFree(ptr_); }
  T* get() const { return ptr_; }
  // Makes room for `count` elements (contents are lost when it grows); zeroed when asked.
  void reserve(size_t count, bool zero = false) {
    count = std::max<size_t>(count, 1);
    if (count > count_) {
      cudaFree(ptr_);
      ptr_ = nullptr;
      check(cudaMalloc(&ptr_, count * sizeof(T)), "cudaMalloc");
      count_ = count;
      zero = true;
    }
    if (zero) check(cudaMemset(ptr_, 0, count_ * sizeof(T)), "cudaMemset");
  }
  void upload(const std::vector<T>& host) {
    reserve(host.size());
    check(cudaMemcpy(ptr_, host.data(), host.size() * sizeof(T), cudaMemcpyHostToDevice), "upload");
  }

 private:
  T* ptr_ = nullptr;
  size_t count_ = 0;
};

// Page-locked host memory, so that copies are asynchronous and can sit in a stream.
template <typename T>
class PinnedArray {
 public:
  ~PinnedArray() { cudaFreeHost(ptr_); }
  T* get() const { return ptr_; }
  void reserve(size_t count) {
    count = std::max<size_t>(count, 1);
    if (count > count_) {
      cudaFreeHost(ptr_);
      ptr_ = nullptr;
      check(cudaMallocHost(&ptr_, count * sizeof(T)), "cudaMallocHost");
      count_ = count;
    }
  }

 private:
  T* ptr_ = nullptr;
  size_t count_ = 0;
};

int next_power_of_two(int x) {
  int p = 1;
  while (p < x) p <<= 1;
  return p;
}

template <typename Real>
class Backend : public DeviceBackend {
 public:
  Backend(const Options& options, const Frame& frame) : options_(options), frame_(frame) {
    check(cudaGetDevice(&device_), "cudaGetDevice");
    check(cudaDeviceGetAttribute(&sms_, cudaDevAttrMultiProcessorCount, device_),
          "cudaDeviceGetAttribute");
    check(cudaDeviceGetAttribute(&max_shared_, cudaDevAttrMaxSharedMemoryPerBlockOptin, device_),
          "cudaDeviceGetAttribute");
    check(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "cudaStreamCreate");
    check(cudaEventCreate(&start_), "cudaEventCreate");
    check(cudaEventCreate(&stop_), "cudaEventCreate");
    tile_bits_ = options.tile == 8 ? 3 : options.tile == 16 ? 4 : (options.grid >= 128 ? 4 : 3);
    // Diagnostic, timing only: FLUIDWEIGHT_TILE_BLOCKS=k runs the tiled kernel as a persistent
    // grid of k blocks per multiprocessor (0: one block per tile).
    if (const char* blocks = std::getenv("FLUIDWEIGHT_TILE_BLOCKS")) {
      tile_blocks_per_sm_ = std::atoi(blocks);
    }
  }

  ~Backend() override {
    if (graph_) cudaGraphExecDestroy(graph_);
    cudaEventDestroy(start_);
    cudaEventDestroy(stop_);
    cudaStreamDestroy(stream_);
  }

  void set_cavities(const std::vector<CavityView>& cavities) override {
    const int n = options_.grid;
    num_cavities_ = static_cast<int>(cavities.size());
    vertex_begin_.assign(1, 0);
    std::vector<int> triangles, tri_cavity, job_begin(1, 0), triangle_begin(1, 0);
    std::vector<gpu::ReduceJob> jobs;
    constexpr int kItemsPerJob = 512;  // two items a thread: latency, not work, bounds this kernel
    for (int c = 0; c < num_cavities_; ++c) {
      const CavityView& v = cavities[c];
      const int offset = vertex_begin_.back(), first_triangle = static_cast<int>(tri_cavity.size());
      for (int k = 0; k < 3 * v.num_triangles; ++k) triangles.push_back(v.triangles[k] + offset);
      tri_cavity.insert(tri_cavity.end(), v.num_triangles, c);
      for (int b = 0; b < v.num_vertices; b += kItemsPerJob) {
        jobs.push_back({c, 0, offset + b, offset + std::min(v.num_vertices, b + kItemsPerJob)});
      }
      for (int b = 0; b < v.num_triangles; b += kItemsPerJob) {
        jobs.push_back({c, 1, first_triangle + b,
                        first_triangle + std::min(v.num_triangles, b + kItemsPerJob)});
      }
      job_begin.push_back(static_cast<int>(jobs.size()));
      vertex_begin_.push_back(offset + v.num_vertices);
      triangle_begin.push_back(static_cast<int>(tri_cavity.size()));
    }
    num_vertices_ = vertex_begin_.back();
    num_triangles_ = static_cast<int>(tri_cavity.size());
    num_jobs_ = static_cast<int>(jobs.size());
    triangles_.upload(triangles);
    tri_cavity_.upload(tri_cavity);
    jobs_.upload(jobs);
    job_begin_.upload(job_begin);
    std::vector<int> first_vertex(vertex_begin_.begin(), vertex_begin_.end() - 1);
    cavity_vertex_begin_.upload(first_vertex);
    cavity_triangle_begin_.upload(triangle_begin);
    setup_blocks_ = (num_triangles_ + gpu::kSetupBlock - 1) / gpu::kSetupBlock;
    xyz_.reserve(3 * static_cast<size_t>(num_vertices_));
    host_xyz_.reserve(3 * static_cast<size_t>(num_vertices_));
    out_.reserve(3 * static_cast<size_t>(num_vertices_));
    host_out_.reserve(3 * static_cast<size_t>(num_vertices_));
    tris_.reserve(num_triangles_);
    partials_.reserve(8 * static_cast<size_t>(num_jobs_));
    states_.reserve(num_cavities_);
    host_states_.reserve(num_cavities_);
    status_.reserve(1);
    host_status_.reserve(1);
    candidates_.reserve(setup_blocks_);
    big_count_.reserve(1);
    big_list_.reserve(num_triangles_);
    if (options_.method == Method::column) {
      if (options_.kernel == Kernel::tiled) {
        tiles_per_side_ = (n + (1 << tile_bits_) - 1) >> tile_bits_;
        tile_count_.reserve(static_cast<size_t>(num_cavities_) * tiles_per_side_ * tiles_per_side_);
        reserve_tiles();
      } else {
        column_count_.reserve(static_cast<size_t>(num_cavities_) * n * n, true);
        reserve_columns();
      }
    }
    invalidate();
  }

  void compute(const std::vector<CavityView>& cavities, std::vector<CavityOutput>& out,
               std::vector<double>& signed_volumes, double& gpu_ms) override {
    double* xyz = host_xyz_.get();
    for (int c = 0; c < num_cavities_; ++c) {
      std::memcpy(xyz + 3 * static_cast<size_t>(vertex_begin_[c]), cavities[c].xyz,
                  3 * sizeof(double) * cavities[c].num_vertices);
    }
    check(cudaMemcpyAsync(xyz_.get(), xyz, 3 * sizeof(double) * num_vertices_,
                          cudaMemcpyHostToDevice, stream_),
          "upload positions");
    const bool hydro = options_.method == Method::hydrostatic;
    const size_t values = (hydro ? 3 : 1) * static_cast<size_t>(num_vertices_);
    for (int attempt = 0;; ++attempt) {
      if (!graph_) capture();
      check(cudaEventRecord(start_, stream_), "cudaEventRecord");
      check(cudaGraphLaunch(graph_, stream_), "cudaGraphLaunch");
      check(cudaEventRecord(stop_, stream_), "cudaEventRecord");
      check(cudaMemcpyAsync(host_out_.get(), out_.get(), values * sizeof(Real),
                            cudaMemcpyDeviceToHost, stream_),
            "download forces");
      check(cudaMemcpyAsync(host_states_.get(), states_.get(),
                            num_cavities_ * sizeof(gpu::CavityState), cudaMemcpyDeviceToHost,
                            stream_),
            "download volumes");
      check(cudaMemcpyAsync(host_status_.get(), status_.get(), sizeof(gpu::Status),
                            cudaMemcpyDeviceToHost, stream_),
            "download status");
      check(cudaStreamSynchronize(stream_), "kernels");
      if (!grow(*host_status_.get()) || attempt == 4) break;
    }
    float ms = 0;
    check(cudaEventElapsedTime(&ms, start_, stop_), "cudaEventElapsedTime");
    gpu_ms = ms;
    static const bool stage_times = std::getenv("FLUIDWEIGHT_KERNEL_TIMES") != nullptr;
    if (stage_times) print_stage_times();
    const Real* values_out = host_out_.get();
    for (int c = 0; c < num_cavities_; ++c) {
      const gpu::CavityState& s = host_states_.get()[c];
      const int per = hydro ? 3 : 1;
      const size_t first = per * static_cast<size_t>(vertex_begin_[c]);
      out[c].values.assign(
          values_out + first,
          values_out + first + per * static_cast<size_t>(cavities[c].num_vertices));
      double sum_heights = 0;
      long long unmatched = 0;
      for (int k = 0; k < gpu::kStripes; ++k) {
        sum_heights += s.sum_heights[k];
        unmatched += static_cast<long long>(s.unmatched[k]);
      }
      out[c].column_volume = s.grid.cell_area * sum_heights;
      out[c].unmatched_columns = unmatched;
      signed_volumes[c] = s.signed_volume;
    }
  }

  // Diagnostic (FLUIDWEIGHT_KERNEL_TIMES=1): each stage launched on its own between events,
  // median of 20, printed to stderr.
  void print_stage_times() {
    const gpu::Batch<Real> b = batch();
    const bool hydro = options_.method == Method::hydrostatic;
    const bool tiled = !hydro && options_.kernel == Kernel::tiled;
    const int zero_out = (hydro ? 3 : 1) * num_vertices_;
    const int zero_tiles = tiled ? num_cavities_ * tiles_per_side_ * tiles_per_side_ : 0;
    std::vector<std::function<void()>> stages = {
        [&] { gpu::launch_reduce(b, zero_out, zero_tiles, stream_); }};
    std::vector<std::string> names = {"reduce"};
    if (hydro) {
      stages.push_back([&] { gpu::launch_hydrostatic(b, stream_); });
      names.push_back("hydrostatic");
    } else if (tiled) {
      stages.push_back([&] { gpu::launch_setup(b, true, stream_); });
      stages.push_back([&] { gpu::launch_tiles(b, sms_, tile_blocks_per_sm_, stream_); });
      names.insert(names.end(), {"setup+bin", "tiles"});
    } else {
      stages.push_back([&] { gpu::launch_setup(b, false, stream_); });
      stages.push_back(
          [&] { gpu::launch_raster(b, options_.kernel == Kernel::leveraging, sms_, stream_); });
      stages.push_back([&] { gpu::launch_columns(b, stream_); });
      names.insert(names.end(), {"setup", "raster", "columns"});
    }
    std::vector<cudaEvent_t> events(stages.size() + 1);
    for (auto& e : events) check(cudaEventCreate(&e), "cudaEventCreate");
    std::vector<std::vector<double>> ms(stages.size());
    for (int r = 0; r < 20; ++r) {
      check(cudaEventRecord(events[0], stream_), "cudaEventRecord");
      for (size_t k = 0; k < stages.size(); ++k) {
        stages[k]();
        check(cudaEventRecord(events[k + 1], stream_), "cudaEventRecord");
      }
      check(cudaEventSynchronize(events.back()), "stages");
      for (size_t k = 0; k < stages.size(); ++k) {
        float t = 0;
        cudaEventElapsedTime(&t, events[k], events[k + 1]);
        ms[k].push_back(t);
      }
    }
    for (size_t k = 0; k < stages.size(); ++k) {
      std::sort(ms[k].begin(), ms[k].end());
      std::fprintf(stderr, "  stage %-12s %8.1f us\n", names[k].c_str(), 1000 * ms[k][10]);
    }
    for (auto& e : events) cudaEventDestroy(e);
  }

  std::vector<double> time_replays(int repeats) override {
    if (!graph_) capture();
    std::vector<double> ms;
    for (int r = 0; r < repeats; ++r) {
      check(cudaEventRecord(start_, stream_), "cudaEventRecord");
      check(cudaGraphLaunch(graph_, stream_), "cudaGraphLaunch");
      check(cudaEventRecord(stop_, stream_), "cudaEventRecord");
      check(cudaEventSynchronize(stop_), "replay");
      float t = 0;
      check(cudaEventElapsedTime(&t, start_, stop_), "cudaEventElapsedTime");
      ms.push_back(t);
    }
    return ms;
  }

 private:
  void invalidate() {
    if (graph_) cudaGraphExecDestroy(graph_);
    graph_ = nullptr;
  }

  void reserve_tiles() {
    size_t tiles = static_cast<size_t>(num_cavities_) * tiles_per_side_ * tiles_per_side_;
    tile_list_.reserve(tiles * tile_capacity_);
    size_t shared = gpu::tile_shared_bytes<Real>(tile_bits_, column_capacity_);
    if (shared > static_cast<size_t>(max_shared_) - 16 * 1024) {
      throw DeviceError("cuda: a column crosses the surface more than " +
                        std::to_string(column_capacity_ / 2) +
                        " times: too many hits for the tiled kernel's shared memory");
    }
    gpu::allow_tile_shared<Real>(shared);
    check(cudaGetLastError(), "cudaFuncSetAttribute");
  }

  void reserve_columns() {
    size_t columns = static_cast<size_t>(num_cavities_) * options_.grid * options_.grid;
    column_z_.reserve(columns * column_capacity_);
    column_tag_.reserve(columns * column_capacity_);
  }

  // Grows what overflowed; true when the call must run again.
  bool grow(const gpu::Status& s) {
    bool again = false;
    if (s.max_tile_count > tile_capacity_) {
      tile_capacity_ = next_power_of_two(s.max_tile_count);
      again = true;
    }
    if (s.max_column_hits > column_capacity_) {
      // A multiple of 4, not a power of two: the tiled kernel's shared memory grows with it
      // (18 hits would take 32 slots, halving the blocks an SM holds).
      column_capacity_ = (s.max_column_hits + 3) / 4 * 4;
      again = true;
    }
    if (again) {
      if (options_.kernel == Kernel::tiled) {
        reserve_tiles();
      } else {
        reserve_columns();
      }
      invalidate();
    }
    return again;
  }

  gpu::Batch<Real> batch() {
    gpu::Batch<Real> b{};
    b.xyz = xyz_.get();
    b.triangles = triangles_.get();
    b.tri_cavity = tri_cavity_.get();
    b.cavity_vertex_begin = cavity_vertex_begin_.get();
    b.cavity_triangle_begin = cavity_triangle_begin_.get();
    b.setup_blocks = setup_blocks_;
    b.num_cavities = num_cavities_;
    b.num_vertices = num_vertices_;
    b.num_triangles = num_triangles_;
    b.frame = frame_;
    b.n = options_.grid;
    const auto& g = options_.gravity;
    b.rho_g = options_.rho * std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    b.jobs = jobs_.get();
    b.cavity_job_begin = job_begin_.get();
    b.num_jobs = num_jobs_;
    b.partials = partials_.get();
    b.cavities = states_.get();
    b.status = status_.get();
    b.tris = tris_.get();
    b.out = out_.get();
    b.column_count = column_count_.get();
    b.column_z = column_z_.get();
    b.column_tag = column_tag_.get();
    b.column_capacity = column_capacity_;
    b.candidates = candidates_.get();
    b.alpha = options_.alpha;
    b.tile_bits = tile_bits_;
    b.tiles_per_side = tiles_per_side_;
    b.tile_count = tile_count_.get();
    b.tile_list = tile_list_.get();
    b.tile_capacity = tile_capacity_;
    b.big_list = big_list_.get();
    b.big_count = big_count_.get();
    const char* phases = std::getenv("FLUIDWEIGHT_TILE_PHASES");  // diagnostic, timing only
    b.diagnostic_phases = phases ? std::atoi(phases) : 3;
    return b;
  }

  // One call's kernels, captured as a graph. Diagnostic: FLUIDWEIGHT_GRAPH_STAGES=k captures
  // only the first k kernels (to time a pipeline's prefix; the results are then wrong).
  void capture() {
    const gpu::Batch<Real> b = batch();
    const bool hydro = options_.method == Method::hydrostatic;
    const bool tiled = !hydro && options_.kernel == Kernel::tiled;
    const int zero_out = (hydro ? 3 : 1) * num_vertices_;
    const int zero_tiles = tiled ? num_cavities_ * tiles_per_side_ * tiles_per_side_ : 0;
    const char* stages_env = std::getenv("FLUIDWEIGHT_GRAPH_STAGES");
    const int stages = stages_env ? std::atoi(stages_env) : 4;
    check(cudaStreamBeginCapture(stream_, cudaStreamCaptureModeThreadLocal), "begin capture");
    if (stages >= 1) gpu::launch_reduce(b, zero_out, zero_tiles, stream_);
    if (hydro) {
      if (stages >= 2) gpu::launch_hydrostatic(b, stream_);
    } else if (tiled) {
      if (stages >= 2) gpu::launch_setup(b, true, stream_);
      if (stages >= 3) gpu::launch_tiles(b, sms_, tile_blocks_per_sm_, stream_);
    } else {
      if (stages >= 2) gpu::launch_setup(b, false, stream_);
      if (stages >= 3) {
        gpu::launch_raster(b, options_.kernel == Kernel::leveraging, sms_, stream_);
      }
      if (stages >= 4) gpu::launch_columns(b, stream_);
    }
    cudaGraph_t graph = nullptr;
    cudaError_t launched = cudaGetLastError();
    check(cudaStreamEndCapture(stream_, &graph), "end capture");
    check(launched, "kernel launch");
    check(cudaGraphInstantiate(&graph_, graph, 0), "cudaGraphInstantiate");
    cudaGraphDestroy(graph);
  }

  Options options_;
  Frame frame_;
  int device_ = 0, sms_ = 1, max_shared_ = 48 * 1024;
  cudaStream_t stream_ = nullptr;
  cudaEvent_t start_ = nullptr, stop_ = nullptr;
  cudaGraphExec_t graph_ = nullptr;
  int num_cavities_ = 0, num_vertices_ = 0, num_triangles_ = 0, num_jobs_ = 0, setup_blocks_ = 1;
  std::vector<int> vertex_begin_;
  int tile_blocks_per_sm_ = 0;  // tiled kernel: persistent grid of this many blocks an SM, or 0
  int tile_bits_ = 4, tiles_per_side_ = 0, tile_capacity_ = 1024, column_capacity_ = 16;

  DeviceArray<double> xyz_, partials_;
  DeviceArray<int> triangles_, tri_cavity_, job_begin_, cavity_vertex_begin_,
      cavity_triangle_begin_;
  DeviceArray<gpu::ReduceJob> jobs_;
  DeviceArray<gpu::CavityState> states_;
  DeviceArray<gpu::Status> status_;
  DeviceArray<gpu::DevTri<Real>> tris_;
  DeviceArray<Real> out_, column_z_;
  DeviceArray<int> column_count_, column_tag_, tile_count_, tile_list_, big_list_, big_count_;
  DeviceArray<unsigned long long> candidates_;
  PinnedArray<double> host_xyz_;
  PinnedArray<Real> host_out_;
  PinnedArray<gpu::CavityState> host_states_;
  PinnedArray<gpu::Status> host_status_;
};

}  // namespace

bool device_present() {
  int count = 0;
  return cudaGetDeviceCount(&count) == cudaSuccess && count > 0;
}

std::string device_name() {
  if (!device_present()) return "";
  int device = 0;
  cudaDeviceProp prop{};
  if (cudaGetDevice(&device) != cudaSuccess ||
      cudaGetDeviceProperties(&prop, device) != cudaSuccess) {
    return "";
  }
  return std::string(prop.name) + ", " + std::to_string(prop.multiProcessorCount) + " SMs, " +
         std::to_string(prop.l2CacheSize >> 20) + " MB L2";
}

std::unique_ptr<DeviceBackend> make_device_backend(const Options& options, const Frame& frame) {
  if (!device_present()) {
    throw DeviceError("cuda: no CUDA device is present (the module is built with CUDA)");
  }
  if (options.precision == Precision::float32) {
    return std::make_unique<Backend<float>>(options, frame);
  }
  return std::make_unique<Backend<double>>(options, frame);
}

}  // namespace fluidweight::detail
