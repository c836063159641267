// The public entry points: options checked once, the implementation chosen at run time.
#include <chrono>
#include <cmath>
#include <sstream>

#include "cpu.hpp"
#include "device.hpp"
#include "fluidweight/fluidweight.hpp"

namespace fluidweight {

using detail::CavityOutput;
using detail::CavityView;

namespace {

void check_options(const Options& o) {
  auto fail = [](const std::string& what) { throw InputError("options: " + what); };
  if (o.grid < 1 || o.grid > detail::kMaxGrid) {
    fail("grid must be in [1, " + std::to_string(detail::kMaxGrid) + "], got " +
         std::to_string(o.grid));
  }
  if (!(o.rho >= 0.0) || !std::isfinite(o.rho)) fail("rho must be finite and >= 0");
  if (!(o.alpha > 0.0) || !std::isfinite(o.alpha)) fail("alpha must be finite and > 0");
  if (o.threads < 0) fail("threads must be >= 0");
  if (o.tile != 0 && o.tile != 8 && o.tile != 16) fail("tile must be 0 (auto), 8 or 16");
}

// Without the overflow of the squares: a sum of forces near 1e154 N still has its length.
double norm3(const std::array<double, 3>& v) { return std::hypot(v[0], v[1], v[2]); }

}  // namespace

struct Context::Impl {
  explicit Impl(const Options& o) : options(o) {
    check_options(o);
    frame = detail::make_frame(o.gravity);
  }

  std::vector<CavityView> views() const {
    std::vector<CavityView> v;
    for (size_t c = 0; c < positions.size(); ++c) {
      v.push_back(CavityView{positions[c], num_vertices[c], triangles[c].data(),
                             static_cast<int>(triangles[c].size() / 3)});
    }
    return v;
  }

  Options options;
  detail::Frame frame;
  std::vector<std::vector<int>> triangles;
  std::vector<int> num_vertices;
  std::vector<std::vector<double>> own_positions;  // copies given to set_cavities
  std::vector<const double*> positions;
  std::vector<Result> results;
  std::vector<CavityOutput> outputs;
  std::unique_ptr<detail::FastColumn> fast;
  std::unique_ptr<detail::DeviceBackend> device;
};

Context::Context(const Options& options) : impl_(std::make_unique<Impl>(options)) {
  if (options.implementation == Implementation::cuda) {
    impl_->device = detail::make_device_backend(options, impl_->frame);
  }
}

Context::~Context() = default;

const Options& Context::options() const { return impl_->options; }

void Context::set_cavities(const std::vector<SurfaceMesh>& cavities) {
  Impl& m = *impl_;
  for (size_t c = 0; c < cavities.size(); ++c) {
    check_closed_surface(cavities[c], "cavity " + std::to_string(c));
  }
  m.triangles.clear();
  m.num_vertices.clear();
  m.own_positions.clear();
  m.positions.clear();
  for (const SurfaceMesh& mesh : cavities) {
    m.triangles.push_back(mesh.triangles);
    m.num_vertices.push_back(mesh.num_vertices());
    m.own_positions.push_back(mesh.vertices);
  }
  for (const auto& p : m.own_positions) m.positions.push_back(p.data());
  m.results.assign(cavities.size(), Result{});
  m.outputs.assign(cavities.size(), CavityOutput{});
  if (m.device) m.device->set_cavities(m.views());
}

void Context::set_positions(const std::vector<const double*>& positions) {
  if (positions.size() != impl_->triangles.size()) {
    throw InputError("set_positions: " + std::to_string(positions.size()) +
                     " position arrays for " + std::to_string(impl_->triangles.size()) +
                     " cavities");
  }
  impl_->positions = positions;
}

const std::vector<Result>& Context::compute() {
  Impl& m = *impl_;
  const Options& o = m.options;
  auto start = std::chrono::steady_clock::now();
  const double rho_g = o.rho * norm3(o.gravity);
  std::vector<CavityView> views = m.views();
  std::vector<double> volumes(views.size(), 0.0);
  double gpu_ms = -1.0;
  if (o.implementation == Implementation::cuda) {
    m.device->compute(views, m.outputs, volumes, gpu_ms);
  } else {
    for (size_t c = 0; c < views.size(); ++c) {
      if (o.method == Method::column && o.implementation == Implementation::cpu_fast) {
        if (!m.fast) m.fast = std::make_unique<detail::FastColumn>(o.threads, o.cpu_kernels);
        m.fast->run(views[c], m.frame, o.grid, rho_g, m.outputs[c], volumes[c]);
        continue;
      }
      volumes[c] = detail::signed_volume(views[c]);
      detail::GridParams grid = detail::grid_for(views[c], m.frame, o.grid, volumes[c]);
      if (o.method == Method::hydrostatic) {
        detail::hydrostatic(views[c], m.frame, grid, rho_g, m.outputs[c]);
      } else if (o.method == Method::column_head && o.implementation == Implementation::cpu_fast) {
        detail::column_head_rows(views[c], m.frame, grid, rho_g, m.outputs[c]);
      } else {
        detail::column_reference(views[c], m.frame, grid, rho_g, o.method == Method::column_head,
                                 m.outputs[c]);
      }
    }
  }
  double wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  // Column method: weights act along gravity. Hydrostatic: the outputs are 3-vectors already.
  const detail::Vec3 down{-m.frame.up.x, -m.frame.up.y, -m.frame.up.z};
  for (size_t c = 0; c < views.size(); ++c) {
    Result& r = m.results[c];
    const CavityOutput& out = m.outputs[c];
    const int nv = views[c].num_vertices;
    r.forces.resize(3 * static_cast<size_t>(nv));
    if (o.method == Method::hydrostatic) {
      r.forces = out.values;
      r.column_volume = std::fabs(volumes[c]);
    } else {
      for (int v = 0; v < nv; ++v) {  // + 0.0: no negative zeros for unloaded nodes
        r.forces[3 * v] = out.values[v] * down.x + 0.0;
        r.forces[3 * v + 1] = out.values[v] * down.y + 0.0;
        r.forces[3 * v + 2] = out.values[v] * down.z + 0.0;
      }
      r.column_volume = out.column_volume;
    }
    std::array<double, 3> sum{0, 0, 0};
    for (int v = 0; v < nv; ++v) {
      for (int d = 0; d < 3; ++d) sum[d] += r.forces[3 * v + d];
    }
    r.total_weight = norm3(sum);
    r.signed_volume = volumes[c];
    r.unmatched_columns = out.unmatched_columns;
    if (o.method != Method::hydrostatic) {
      const detail::GridParams grid = detail::grid_for(views[c], m.frame, o.grid, volumes[c]);
      r.column_weight = grid.empty ? 0.0 : rho_g * grid.cell_area * (grid.u1 - grid.u0);
    }
    r.timings.wall_ms = wall_ms;
    r.timings.gpu_ms = gpu_ms;
  }
  return m.results;
}

std::vector<double> Context::time_device_replays(int repeats) {
  if (!impl_->device) throw DeviceError("time_device_replays: the context does not use CUDA");
  return impl_->device->time_replays(repeats);
}

Result compute(const SurfaceMesh& mesh, const Options& options) {
  return compute_batch({mesh}, options).front();
}

std::vector<Result> compute_batch(const std::vector<SurfaceMesh>& cavities,
                                  const Options& options) {
  Context context(options);
  context.set_cavities(cavities);
  return context.compute();
}

bool cuda_available() { return detail::device_present(); }

std::string cuda_device_name() { return detail::device_name(); }

std::string to_string(Method m) {
  return m == Method::column ? "column" : m == Method::column_head ? "column_head" : "hydrostatic";
}

std::string to_string(Kernel k) {
  switch (k) {
    case Kernel::leveraging:
      return "leveraging";
    case Kernel::triangle_parallel:
      return "triangle_parallel";
    case Kernel::fused:
      return "fused";
    case Kernel::automatic:
      return "automatic";
    default:
      return "tiled";
  }
}

std::string to_string(Precision p) { return p == Precision::float32 ? "float32" : "float64"; }

std::string to_string(Implementation i) {
  switch (i) {
    case Implementation::cpu_reference:
      return "cpu_reference";
    case Implementation::cpu_fast:
      return "cpu_fast";
    default:
      return "cuda";
  }
}

Method parse_method(const std::string& name) {
  if (name == "column") return Method::column;
  if (name == "column_head") return Method::column_head;
  if (name == "hydrostatic") return Method::hydrostatic;
  throw InputError("method: '" + name + "' is not one of column, column_head, hydrostatic");
}

Kernel parse_kernel(const std::string& name) {
  for (Kernel k : {Kernel::leveraging, Kernel::triangle_parallel, Kernel::tiled, Kernel::fused,
                   Kernel::automatic}) {
    if (name == to_string(k)) return k;
  }
  throw InputError("kernel: '" + name +
                   "' is not one of leveraging, triangle_parallel, tiled, fused, automatic");
}

Precision parse_precision(const std::string& name) {
  if (name == "float32") return Precision::float32;
  if (name == "float64") return Precision::float64;
  throw InputError("precision: '" + name + "' is not one of float32, float64");
}

}  // namespace fluidweight
