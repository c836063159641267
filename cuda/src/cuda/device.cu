// The CUDA backend: device buffers kept between calls, the call captured once as a CUDA graph
// and replayed, fixed-capacity buffers grown (and the graph recaptured) when a call reports an
// overflow. The fused and tiled kernels' own state is in device_fused.cu and device_tiled.cu.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "../device.hpp"
#include "device_buffers.cuh"
#include "device_common.cuh"
#include "device_fused.cuh"
#include "device_tiled.cuh"
#include "kernel_choice.hpp"

namespace fluidweight::detail {
namespace {

int device_attribute(cudaDeviceAttr attribute) {
  int device = 0, value = 0;
  check(cudaGetDevice(&device), "cudaGetDevice");
  check(cudaDeviceGetAttribute(&value, attribute, device), "cudaDeviceGetAttribute");
  return value;
}

template <typename Real>
class Backend : public DeviceBackend {
 public:
  Backend(const Options& options, const Frame& frame)
      : options_(options),
        frame_(frame),
        sms_(device_attribute(cudaDevAttrMultiProcessorCount)),
        max_shared_(device_attribute(cudaDevAttrMaxSharedMemoryPerBlockOptin)),
        fused_(options, max_shared_),
        tiled_(options, sms_, max_shared_) {
    check(cudaStreamCreateWithFlags(&stream_, cudaStreamNonBlocking), "cudaStreamCreate");
    check(cudaEventCreate(&start_), "cudaEventCreate");
    check(cudaEventCreate(&stop_), "cudaEventCreate");
    kernel_ = options.kernel;
  }

  ~Backend() override {
    invalidate();
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
      // The signed volume's triangle ranges only where Step 2 does not assume the
      // orientation (assumed_orientation()): the hydrostatic load needs it first.
      for (int b = 0; options_.method == Method::hydrostatic && b < v.num_triangles;
           b += kItemsPerJob) {
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
    acc_[0].out.reserve(3 * static_cast<size_t>(num_vertices_));
    host_out_.reserve(3 * static_cast<size_t>(num_vertices_));
    tris_.reserve(num_triangles_);
    partials_.reserve(8 * static_cast<size_t>(num_jobs_));
    acc_[0].states.reserve(num_cavities_);
    host_states_.reserve(num_cavities_);
    acc_[0].status.reserve(1);
    host_status_.reserve(1);
    candidates_.reserve(setup_blocks_);
    big_count_.reserve(1);
    big_list_.reserve(num_triangles_);
    kernel_ = options_.kernel;
    if (columns() && kernel_ == Kernel::automatic) {
      kernel_ = automatic_column_kernel(cavities, frame_, n);
    }
    // Every column kernel assumes each cavity's orientation (+1 at first, then the sign the
    // previous call found) and runs the call again when the signed volume disagrees.
    host_orientation_.assign(num_cavities_, 1);
    orientation_.upload(host_orientation_);
    if (fused()) {
      fused_.set_cavities(cavities, vertex_begin_, triangle_begin, acc_);
      parity_ = 0;
    }
    tiled_.set_cavities(tiled(), num_cavities_, num_triangles_, column_capacity_);
    if (columns() && !tiled() && !fused()) {
      column_count_.reserve(static_cast<size_t>(num_cavities_) * n * n, true);
      reserve_columns();
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
      if (!graphs_[0]) capture();
      // Two graphs used by alternate calls (alternating()); the fused kernel's also alternate
      // between two sets of accumulators.
      const int graph = alternating() ? parity_ : 0;
      parity_ ^= alternating() ? 1 : 0;
      const int parity = fused() ? graph : 0;
      check(cudaEventRecord(start_, stream_), "cudaEventRecord");
      check(cudaGraphLaunch(graphs_[graph], stream_), "cudaGraphLaunch");
      check(cudaEventRecord(stop_, stream_), "cudaEventRecord");
      check(cudaMemcpyAsync(host_out_.get(), acc_[parity].out.get(), values * sizeof(Real),
                            cudaMemcpyDeviceToHost, stream_),
            "download forces");
      check(cudaMemcpyAsync(host_states_.get(), acc_[parity].states.get(),
                            num_cavities_ * sizeof(gpu::CavityState), cudaMemcpyDeviceToHost,
                            stream_),
            "download volumes");
      check(cudaMemcpyAsync(host_status_.get(), acc_[parity].status.get(), sizeof(gpu::Status),
                            cudaMemcpyDeviceToHost, stream_),
            "download status");
      check(cudaStreamSynchronize(stream_), "kernels");
      const bool reoriented = assumed_orientation() && check_orientation();
      if (!(grow(*host_status_.get()) || reoriented) || attempt == 4) break;
    }
    float ms = 0;
    check(cudaEventElapsedTime(&ms, start_, stop_), "cudaEventElapsedTime");
    gpu_ms = ms;
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
      signed_volumes[c] = assumed_orientation() ? fused_volume(s) : s.signed_volume;
    }
  }

  std::vector<double> time_replays(int repeats) override {
    if (!graphs_[0]) capture();
    std::vector<double> ms;
    for (int r = 0; r < repeats; ++r) {
      const int graph = alternating() ? parity_ : 0;
      parity_ ^= alternating() ? 1 : 0;
      check(cudaEventRecord(start_, stream_), "cudaEventRecord");
      check(cudaGraphLaunch(graphs_[graph], stream_), "cudaGraphLaunch");
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
    for (cudaGraphExec_t& g : graphs_) {
      if (g) cudaGraphExecDestroy(g);
      g = nullptr;
    }
  }

  // Either column method: the same kernels, column_head's sections also loading ceilings.
  bool columns() const { return options_.method != Method::hydrostatic; }
  bool fused() const { return columns() && kernel_ == Kernel::fused; }
  bool tiled() const { return columns() && kernel_ == Kernel::tiled; }

  // Step 2 takes each cavity's orientation from orientation_ (checked after the call) rather
  // than from reduce_kernel's signed volume: every column kernel (the signed volume's gathers
  // of three corners a triangle were the longest part of reduce_kernel, on every call's path).
  bool assumed_orientation() const { return columns(); }

  // Alternate calls replay two graphs: the fused kernel's two sets of accumulators, or the tiled
  // kernel's two tile orders (one read by the call's tiles, the other written for the next).
  bool alternating() const { return fused() || tiled_.ordered(); }

  // The signed volume summed by stripes (fused_kernel and setup_kernel with an assumed
  // orientation).
  double fused_volume(const gpu::CavityState& s) const {
    double v = 0;
    for (int k = 0; k < gpu::kStripes; ++k) v += s.volume6[k];
    return v / 6.0;
  }

  // After a call: true (and the assumed orientations corrected) when a cavity's signed volume
  // has the other sign than the one its Step 2 assumed.
  bool check_orientation() {
    bool changed = false;
    for (int c = 0; c < num_cavities_; ++c) {
      const int sign = fused_volume(host_states_.get()[c]) < 0 ? -1 : 1;
      if (sign != host_orientation_[c]) {
        host_orientation_[c] = sign;
        changed = true;
      }
    }
    if (changed) orientation_.upload(host_orientation_);
    return changed;
  }

  void reserve_columns() {
    if (gpu::column_shared_bytes<Real>(column_capacity_, 32) >
        static_cast<size_t>(max_shared_) - 8 * 1024) {
      throw DeviceError("cuda: a column crosses the surface more than " +
                        std::to_string(column_capacity_) +
                        " times: too many hits for the column kernel's shared memory");
    }
    size_t columns = static_cast<size_t>(num_cavities_) * options_.grid * options_.grid;
    column_z_.reserve(columns * column_capacity_);
    column_tag_.reserve(columns * column_capacity_);
  }

  // Grows what overflowed; true when the call must run again.
  bool grow(const gpu::Status& s) {
    if (fused()) {
      const bool again = fused_.grow(s);
      if (again) invalidate();
      return again;
    }
    bool again = tiled_.grow_lists(s.max_tile_count);
    if (s.max_column_hits > column_capacity_) {
      // A multiple of 4, not a power of two: the tiled kernel's shared memory grows with it
      // (18 hits would take 32 slots, halving the blocks an SM holds).
      column_capacity_ = (s.max_column_hits + 3) / 4 * 4;
      again = true;
    }
    if (again) {
      if (kernel_ == Kernel::tiled) {
        tiled_.reserve(column_capacity_);
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
    b.head = options_.method == Method::column_head;
    b.jobs = jobs_.get();
    b.cavity_job_begin = job_begin_.get();
    b.num_jobs = num_jobs_;
    b.partials = partials_.get();
    b.cavities = acc_[0].states.get();
    b.status = acc_[0].status.get();
    b.tris = tris_.get();
    b.out = acc_[0].out.get();
    b.column_count = column_count_.get();
    b.column_z = column_z_.get();
    b.column_tag = column_tag_.get();
    b.column_capacity = column_capacity_;
    b.candidates = candidates_.get();
    b.alpha = options_.alpha;
    b.big_list = big_list_.get();
    b.big_count = big_count_.get();
    b.orientation = assumed_orientation() ? orientation_.get() : nullptr;
    tiled_.fill(b);
    return b;
  }

  // One call's kernels, captured as a graph; two graphs when alternate calls differ.
  void capture() {
    const gpu::Batch<Real> b = batch();
    const bool hydro = options_.method == Method::hydrostatic;
    const int zero_out = (hydro ? 3 : 1) * num_vertices_;
    const int zero_tiles = tiled() ? tiled_.tiles() : 0;
    for (int g = 0; g < (alternating() ? 2 : 1); ++g) {
      check(cudaStreamBeginCapture(stream_, cudaStreamCaptureModeThreadLocal), "begin capture");
      if (fused()) {
        fused_.launch(b, acc_[g], acc_[g ^ 1], stream_);
      } else {
        gpu::launch_reduce(b, zero_out, zero_tiles, stream_);
        if (hydro) {
          gpu::launch_hydrostatic(b, stream_);
        } else if (tiled()) {
          tiled_.launch(b, g, stream_);
        } else {
          gpu::launch_setup(b, false, stream_);
          gpu::launch_raster(b, kernel_ == Kernel::leveraging, sms_, stream_);
          gpu::launch_columns(b, max_shared_, stream_);
        }
      }
      end_capture(graphs_[g]);
    }
  }

  void end_capture(cudaGraphExec_t& exec) {
    cudaGraph_t graph = nullptr;
    cudaError_t launched = cudaGetLastError();
    check(cudaStreamEndCapture(stream_, &graph), "end capture");
    check(launched, "kernel launch");
    check(cudaGraphInstantiate(&exec, graph, 0), "cudaGraphInstantiate");
    cudaGraphDestroy(graph);
  }

  Options options_;
  Frame frame_;
  int sms_ = 1, max_shared_ = 48 * 1024;
  cudaStream_t stream_ = nullptr;
  cudaEvent_t start_ = nullptr, stop_ = nullptr;
  cudaGraphExec_t graphs_[2] = {nullptr, nullptr};  // one for each of alternate calls
  Kernel kernel_ = Kernel::tiled;                   // the kernel in use (automatic resolved)
  int num_cavities_ = 0, num_vertices_ = 0, num_triangles_ = 0, num_jobs_ = 0, setup_blocks_ = 1;
  std::vector<int> vertex_begin_;
  int column_capacity_ = 16;  // hits a column holds (paper and tiled kernels), grown on overflow
  int parity_ = 0;
  std::vector<int> host_orientation_;  // the orientation each cavity's Step 2 assumes
  DeviceArray<int> orientation_;
  FusedKernel<Real> fused_;
  TiledKernel<Real> tiled_;
  Accumulators<Real> acc_[2];  // the second for the fused kernel's alternate calls

  DeviceArray<double> xyz_, partials_;
  DeviceArray<int> triangles_, tri_cavity_, job_begin_, cavity_vertex_begin_,
      cavity_triangle_begin_;
  DeviceArray<gpu::ReduceJob> jobs_;
  DeviceArray<gpu::DevTri<Real>> tris_;
  DeviceArray<Real> column_z_;
  DeviceArray<int> column_count_, column_tag_, big_list_, big_count_;
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
