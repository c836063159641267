// The CUDA backend: device buffers kept between calls, the call captured once as a CUDA graph
// and replayed, fixed-capacity buffers grown (and the graph recaptured) when a call reports an
// overflow.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "../device.hpp"
#include "device_buffers.cuh"
#include "device_common.cuh"
#include "kernel_choice.hpp"

namespace fluidweight::detail {
namespace {

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
    check(cudaStreamCreateWithFlags(&side_, cudaStreamNonBlocking), "cudaStreamCreate");
    check(cudaEventCreateWithFlags(&fork_, cudaEventDisableTiming), "cudaEventCreate");
    check(cudaEventCreateWithFlags(&join_, cudaEventDisableTiming), "cudaEventCreate");
    tile_bits_ = options.tile == 8 ? 3 : options.tile == 16 ? 4 : (options.grid >= 128 ? 4 : 3);
    kernel_ = options.kernel;
    // The fused kernel's tile: Options::tile, else chosen by choose_fused_tile().
    fused_preferred_bits_ = options.tile == 8 ? 3 : options.tile == 16 ? 4 : 0;
  }

  ~Backend() override {
    invalidate();
    cudaEventDestroy(start_);
    cudaEventDestroy(stop_);
    cudaEventDestroy(fork_);
    cudaEventDestroy(join_);
    cudaStreamDestroy(side_);
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
    kernel_ = options_.kernel;
    if (options_.method == Method::column && kernel_ == Kernel::automatic) {
      // Fine meshes on coarse grids: most triangles cover no column or one, nothing needs
      // balancing, and the paper's kernel skips the binning and tiles that the tiled and fused
      // kernels pay for (docs/fluidweight.md, "When each kernel wins"). Only while no box is
      // large: leveraging's k comes from the mean, and a few large boxes among small ones would
      // each be walked by one thread. Otherwise tiled: with its kernels started overlapped it
      // is faster than the fused one on every case measured, small cavities included.
      const CandidateCounts c = candidate_counts(cavities, frame_, n);
      kernel_ = c.mean <= kAutomaticLeveragingMean && c.max <= kAutomaticLeveragingMax
                    ? Kernel::leveraging
                    : Kernel::tiled;
    }
    // Every column kernel assumes each cavity's orientation (+1 at first, then the sign the
    // previous call found) and runs the call again when the signed volume disagrees.
    host_orientation_.assign(num_cavities_, 1);
    orientation_.upload(host_orientation_);
    if (options_.method == Method::column && kernel_ == Kernel::fused) {
      set_fused_cavities(cavities, triangle_begin);
    }
    if (options_.method == Method::column) {
      if (kernel_ == Kernel::tiled) {
        tiles_per_side_ = (n + (1 << tile_bits_) - 1) >> tile_bits_;
        tile_count_.reserve(static_cast<size_t>(num_cavities_) * tiles_per_side_ * tiles_per_side_ *
                            gpu::kCountStride);
        reserve_tiles();
      } else if (kernel_ != Kernel::fused) {
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
      if (!graphs_[0]) capture();
      // Two graphs used by alternate calls (alternating()); the fused kernel's also alternate
      // between two sets of accumulators.
      const int graph = alternating() ? parity_ : 0;
      parity_ ^= alternating() ? 1 : 0;
      const int parity = fused() ? graph : 0;
      check(cudaEventRecord(start_, stream_), "cudaEventRecord");
      check(cudaGraphLaunch(graphs_[graph], stream_), "cudaGraphLaunch");
      check(cudaEventRecord(stop_, stream_), "cudaEventRecord");
      check(cudaMemcpyAsync(host_out_.get(), (parity ? out2_ : out_).get(), values * sizeof(Real),
                            cudaMemcpyDeviceToHost, stream_),
            "download forces");
      check(cudaMemcpyAsync(host_states_.get(), (parity ? states2_ : states_).get(),
                            num_cavities_ * sizeof(gpu::CavityState), cudaMemcpyDeviceToHost,
                            stream_),
            "download volumes");
      check(cudaMemcpyAsync(host_status_.get(), (parity ? status2_ : status_).get(),
                            sizeof(gpu::Status), cudaMemcpyDeviceToHost, stream_),
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

  bool fused() const { return options_.method == Method::column && kernel_ == Kernel::fused; }

  // Step 2 takes each cavity's orientation from orientation_ (checked after the call) rather
  // than from reduce_kernel's signed volume: every column kernel (the signed volume's gathers
  // of three corners a triangle were the longest part of reduce_kernel, on every call's path).
  bool assumed_orientation() const { return options_.method == Method::column; }

  // Alternate calls replay two graphs: the fused kernel's two sets of accumulators, or the tiled
  // kernel's two tile orders (one read by the call's tiles, the other written for the next).
  bool alternating() const { return fused() || use_tile_order(); }

  // The fused kernel's inputs: corners packed per triangle, vertex ranges, the orientation
  // assumed per cavity; both sets of accumulators cleared. Chooses its tile.
  void set_fused_cavities(const std::vector<CavityView>& cavities,
                          const std::vector<int>& triangle_begin) {
    triangle_begin_ = triangle_begin;
    std::vector<unsigned long long> corners;
    std::vector<int> begin(1, 0);
    max_vertices_ = 0;
    for (const CavityView& v : cavities) {
      for (int t = 0; t < v.num_triangles; ++t) {
        const int* c = v.triangles + 3 * t;
        corners.push_back(static_cast<unsigned long long>(c[0]) |
                          (static_cast<unsigned long long>(c[1]) << 21) |
                          (static_cast<unsigned long long>(c[2]) << 42));
      }
      begin.push_back(begin.back() + v.num_vertices);
      max_vertices_ = std::max(max_vertices_, v.num_vertices);
    }
    const bool fits = max_vertices_ < (1 << 21) && choose_fused_tile();
    if (!fits) {
      throw DeviceError(
          "cuda: the cavities (their tiles' triangles and hits) do not fit the fused kernel's "
          "shared memory (use "
          "tiled)");
    }
    corners_.upload(corners);
    vertex_begin_all_.upload(begin);
    const size_t values = 3 * static_cast<size_t>(num_vertices_);
    out_.reserve(values, true);
    out2_.reserve(values, true);
    states_.reserve(num_cavities_, true);
    states2_.reserve(num_cavities_, true);
    status_.reserve(1, true);
    status2_.reserve(1, true);
    parity_ = 0;
  }

  // The tile (the preferred one, else 16 columns from N = 128 on, else 8) and the cluster of
  // tiles: the most blocks (up to 16) for the least padding of the grid to whole clusters, among
  // the shapes whose shared memory the device gives.
  bool choose_fused_tile() {
    for (int bits = fused_preferred_bits_ > 0 ? fused_preferred_bits_
                                              : (options_.grid >= 128 ? 4 : 3);
         bits >= 3; --bits) {
      const int tiles = (options_.grid + (1 << bits) - 1) >> bits;
      std::vector<std::pair<double, std::pair<int, int>>> shapes;
      for (int cx = 1; cx <= std::min(tiles, 16); ++cx) {
        for (int cy = 1; cy <= std::min(tiles, 16 / cx); ++cy) {
          const double waste = static_cast<double>((tiles + cx - 1) / cx * cx) *
                               ((tiles + cy - 1) / cy * cy) / (static_cast<double>(tiles) * tiles);
          shapes.push_back({-(cx * cy) / (waste * waste), {cx, cy}});
        }
      }
      std::sort(shapes.begin(), shapes.end());
      for (const auto& shape : shapes) {
        const int cx = shape.second.first, cy = shape.second.second;
        const int slice = (max_vertices_ + cx * cy - 1) / (cx * cy);
        const size_t bytes = gpu::fused_shared_bytes<Real>(bits, std::max(slice, 1),
                                                           fused_column_capacity_, item_capacity_);
        if (bytes > static_cast<size_t>(max_shared_)) continue;
        const int resident = gpu::fused_clusters<Real>(bits, cx, cy, bytes);
        if (resident > 0) {
          fused_tile_bits_ = bits;
          cluster_x_ = cx;
          cluster_y_ = cy;
          slice_vertices_ = std::max(slice, 1);
          return true;
        }
      }
    }
    return false;
  }

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

  gpu::Batch<Real> fused_batch(int parity) {
    gpu::Batch<Real> b = batch();
    b.out = (parity ? out2_ : out_).get();
    b.cavities = (parity ? states2_ : states_).get();
    b.status = (parity ? status2_ : status_).get();
    b.column_capacity = fused_column_capacity_;
    return b;
  }

  gpu::FusedArgs<Real> fused_args(int parity) {
    gpu::FusedArgs<Real> f{};
    f.corners = corners_.get();
    f.vertex_begin = vertex_begin_all_.get();
    for (int c = 0; c <= std::min(num_cavities_, gpu::FusedArgs<Real>::kInlineCavities); ++c) {
      f.inline_vertex_begin[c] = vertex_begin_[c];
      f.inline_triangle_begin[c] = triangle_begin_[c];
    }
    f.orientation = orientation_.get();
    f.tiles_per_side = (options_.grid + (1 << fused_tile_bits_) - 1) >> fused_tile_bits_;
    f.cluster_x = cluster_x_;
    f.cluster_y = cluster_y_;
    f.slice_vertices = slice_vertices_;
    f.item_capacity = item_capacity_;
    f.next_out = (parity ? out_ : out2_).get();
    f.next_out_count = num_vertices_;
    f.next_cavities = (parity ? states_ : states2_).get();
    f.next_status = (parity ? status_ : status2_).get();
    return f;
  }

  // The tiled kernel takes its tiles heaviest first when they need more than one and a half
  // waves of blocks: otherwise the last blocks started decide the kernel's end. The order is
  // the previous call's counts sorted by order_kernel beside this call's tile kernel (one
  // block sorting on the call's own path cost more than the order gains); a control loop's
  // surfaces move little from call to call, and any order of the tiles gives the same result.
  bool use_tile_order() const {
    if (options_.method != Method::column || kernel_ != Kernel::tiled) return false;
    const int tiles = num_cavities_ * tiles_per_side_ * tiles_per_side_;
    if (tiles > gpu::max_ordered_tiles()) return false;
    const size_t shared = gpu::tile_shared_bytes<Real>(tile_bits_, column_capacity_);
    const int per_sm =
        std::max(1, gpu::tile_resident_blocks<Real>(tile_bits_, half_round(), shared));
    // From one and a half waves on: below, the tiles gain more from starting overlapped with
    // the setup kernel (overlap_level(), not with the order) than from the order.
    return 2 * tiles > 3 * per_sm * sms_;
  }

  // With the tile order, the blocks past the previous call's first empty position check
  // several of those tiles each (tile_kernel): over half of a fine grid's tiles can be empty,
  // and a block each held a block slot for its launch and two dependent loads.
  bool group_empty_tiles() const { return use_tile_order(); }

  // The tiled kernel stages half as many triangles a round (TILE^2 / 2) when that lets an SM
  // hold more of its blocks (many hit slots a column); a tile of more triangles then takes
  // more rounds. Tiles of 16 columns only: with tiles of 8 (N < 128) the blocks an SM holds
  // are not what limits, and rounds of 32 triangles cost more than they gain.
  bool half_round() const {
    if (tile_bits_ != 4) return false;
    const size_t shared = gpu::tile_shared_bytes<Real>(tile_bits_, column_capacity_);
    return gpu::tile_resident_blocks<Real>(tile_bits_, true, shared) >
           gpu::tile_resident_blocks<Real>(tile_bits_, false, shared);
  }

  // Which kernels start overlapped with the one before them (launch_overlapped; the measured
  // effects are in docs/fluidweight.md): setup_kernel always (its corner loads and launch
  // overlap reduce_kernel's end); the tile kernel only without the tile order (with it, its
  // waiting blocks fill the GPU before the order kernel's one block starts, which then ends
  // after the tiles) and only with few triangles a tile (else the early blocks of a few heavy
  // tiles sit beside the setup kernel's); the paper's raster and column kernels not (slower).
  int overlap_level() const {
    const long long tiles =
        static_cast<long long>(num_cavities_) * tiles_per_side_ * tiles_per_side_;
    const bool light = num_triangles_ <= kOverlapTrianglesPerTile * tiles;
    return options_.method == Method::column && kernel_ == Kernel::tiled && !use_tile_order() &&
                   light
               ? 2
               : 1;
  }

  void launch_tile_order(int into, cudaStream_t stream) {
    gpu::launch_tile_order(tile_count_.get(), big_count_.get(),
                           num_cavities_ * tiles_per_side_ * tiles_per_side_,
                           (into ? tile_order2_ : tile_order_).get(), stream);
  }

  void reserve_tiles() {
    size_t tiles = static_cast<size_t>(num_cavities_) * tiles_per_side_ * tiles_per_side_;
    tile_list_.reserve(tiles * tile_capacity_);
    // Both orders start as the grid's (the first call has no counts before it); entry `tiles`
    // is where the tiles empty at the previous call begin: none yet.
    std::vector<int> identity(tiles + 1);
    for (size_t t = 0; t <= tiles; ++t) identity[t] = static_cast<int>(t);
    tile_order_.upload(identity);
    tile_order2_.upload(identity);
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
      bool again = false;
      if (s.max_tile_count > item_capacity_) {
        item_capacity_ = next_power_of_two(s.max_tile_count);
        again = true;
      }
      if (s.max_column_hits > fused_column_capacity_) {
        fused_column_capacity_ = (s.max_column_hits + 3) / 4 * 4;
        again = true;
      }
      if (again) {
        if (!choose_fused_tile()) {
          throw DeviceError("cuda: a tile's triangles (" + std::to_string(s.max_tile_count) +
                            ") or a column's hits (" + std::to_string(s.max_column_hits) +
                            ") do not fit the fused kernel's shared memory (use tiled)");
        }
        invalidate();
      }
      return again;
    }
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
      if (kernel_ == Kernel::tiled) {
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
    b.tile_order = use_tile_order() ? tile_order_.get() : nullptr;
    b.orientation = assumed_orientation() ? orientation_.get() : nullptr;
    b.overlap = overlap_level();
    b.half_round = half_round();
    b.group_empty = group_empty_tiles();
    return b;
  }

  // One call's kernels, captured as a graph.
  void capture() {
    const gpu::Batch<Real> b = batch();
    const bool hydro = options_.method == Method::hydrostatic;
    const bool tiled = !hydro && kernel_ == Kernel::tiled;
    const int zero_out = (hydro ? 3 : 1) * num_vertices_;
    const int zero_tiles = tiled ? num_cavities_ * tiles_per_side_ * tiles_per_side_ : 0;
    if (fused()) {
      for (int parity = 0; parity < 2; ++parity) {
        check(cudaStreamBeginCapture(stream_, cudaStreamCaptureModeThreadLocal), "begin capture");
        gpu::launch_fused(fused_batch(parity), fused_args(parity), fused_tile_bits_, stream_);
        end_capture(graphs_[parity]);
      }
      return;
    }
    check(cudaStreamBeginCapture(stream_, cudaStreamCaptureModeThreadLocal), "begin capture");
    gpu::launch_reduce(b, zero_out, zero_tiles, stream_);
    if (hydro) {
      gpu::launch_hydrostatic(b, stream_);
    } else if (tiled && b.tile_order) {
      // Graph g's tiles read order g; the order kernel, forked beside them, writes the other.
      for (int g = 0; g < 2; ++g) {
        gpu::Batch<Real> bg = b;
        bg.tile_order = (g ? tile_order2_ : tile_order_).get();
        if (g == 1) {
          check(cudaStreamBeginCapture(stream_, cudaStreamCaptureModeThreadLocal), "begin capture");
          gpu::launch_reduce(b, zero_out, zero_tiles, stream_);
        }
        gpu::launch_setup(bg, true, stream_);
        // The order's node is made first, so that its one block starts before the tiles'.
        check(cudaEventRecord(fork_, stream_), "cudaEventRecord");
        check(cudaStreamWaitEvent(side_, fork_, 0), "cudaStreamWaitEvent");
        launch_tile_order(g ^ 1, side_);
        check(cudaEventRecord(join_, side_), "cudaEventRecord");
        gpu::launch_tiles(bg, stream_);
        check(cudaStreamWaitEvent(stream_, join_, 0), "cudaStreamWaitEvent");
        end_capture(graphs_[g]);
      }
      return;
    } else if (tiled) {
      gpu::launch_setup(b, true, stream_);
      gpu::launch_tiles(b, stream_);
    } else {
      gpu::launch_setup(b, false, stream_);
      gpu::launch_raster(b, kernel_ == Kernel::leveraging, sms_, stream_);
      gpu::launch_columns(b, max_shared_, stream_);
    }
    end_capture(graphs_[0]);
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
  int device_ = 0, sms_ = 1, max_shared_ = 48 * 1024;
  cudaStream_t stream_ = nullptr, side_ = nullptr;  // side_: the tile order's branch
  cudaEvent_t fork_ = nullptr, join_ = nullptr;
  cudaEvent_t start_ = nullptr, stop_ = nullptr;
  cudaGraphExec_t graphs_[2] = {nullptr, nullptr};  // fused: one per set of accumulators
  Kernel kernel_ = Kernel::tiled;                   // the kernel in use (automatic resolved)
  int num_cavities_ = 0, num_vertices_ = 0, num_triangles_ = 0, num_jobs_ = 0, setup_blocks_ = 1;
  std::vector<int> vertex_begin_;
  int tile_bits_ = 4, tiles_per_side_ = 0, tile_capacity_ = 1024, column_capacity_ = 16;
  // Fused kernel: tile (bits), hits per column, triangles a tile keeps, the vertex table, the
  // call's set of accumulators, the orientation each cavity's Step 2 assumes.
  // Automatic takes leveraging when the mean candidate count a triangle is at most this and
  // no triangle's box holds more columns than the second.
  static constexpr double kAutomaticLeveragingMean = 4, kAutomaticLeveragingMax = 64;
  // The tile kernel starts overlapped with the setup kernel up to this many triangles a tile
  // on average (overlap_level()).
  static constexpr long long kOverlapTrianglesPerTile = 64;
  int fused_tile_bits_ = 4, fused_preferred_bits_ = 0, fused_column_capacity_ = 4,
      item_capacity_ = 512, max_vertices_ = 0, parity_ = 0, cluster_x_ = 1, cluster_y_ = 1,
      slice_vertices_ = 1;
  std::vector<int> host_orientation_, triangle_begin_;
  DeviceArray<unsigned long long> corners_;
  DeviceArray<int> vertex_begin_all_, orientation_;
  DeviceArray<gpu::CavityState> states2_;
  DeviceArray<gpu::Status> status2_;

  DeviceArray<double> xyz_, partials_;
  DeviceArray<int> triangles_, tri_cavity_, job_begin_, cavity_vertex_begin_,
      cavity_triangle_begin_;
  DeviceArray<gpu::ReduceJob> jobs_;
  DeviceArray<gpu::CavityState> states_;
  DeviceArray<gpu::Status> status_;
  DeviceArray<gpu::DevTri<Real>> tris_;
  DeviceArray<Real> out_, out2_, column_z_;
  DeviceArray<int> column_count_, column_tag_, tile_count_, tile_list_, big_list_, big_count_,
      tile_order_, tile_order2_;
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
