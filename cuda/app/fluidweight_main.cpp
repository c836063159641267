// fluidweight MESH [--grid N] [--method column|column_head|hydrostatic] [--device cpu|cuda]
//             [--kernel NAME] [--alpha A] [--rho R] [--gravity gx,gy,gz] [--repeat K]
//             [--forces FILE] [--json]
//
// Reads a closed surface (.obj, .off, .stl, .msh), computes the liquid's weight on its nodes,
// prints the volumes, the total weight and the median time over the repeats (a JSON object with
// --json), and writes one line "fx fy fz" per vertex with --forces.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "fluidweight/fluidweight.hpp"
#include "fluidweight/mesh_io.hpp"

namespace fw = fluidweight;

namespace {

const char* kUsage =
    "usage: fluidweight MESH [--grid N] [--method column|column_head|hydrostatic]\n"
    "                   [--device cpu|cuda] [--kernel NAME] [--alpha A] [--rho R]\n"
    "                   [--gravity gx,gy,gz] [--repeat K] [--forces FILE] [--json]\n"
    "  MESH      closed triangle surface: .obj, .off, .stl (ASCII or binary), .msh (ASCII)\n"
    "  --grid    columns per side of the N x N grid (default 200)\n"
    "  --method  column (the paper's column method, default), column_head (its columns with the\n"
    "            pressure at each floor's and ceiling's depth) or hydrostatic (closed form)\n"
    "  --device  cpu (default) or cuda\n"
    "  --kernel  cpu: fast (all threads, default) or reference;\n"
    "            cuda: tiled (default), fused, automatic, leveraging or triangle_parallel,\n"
    "            optionally followed by :float64 (default) or :float32, e.g. fused:float32\n"
    "  --alpha   leveraging kernel: k = max(1, floor(alpha c)) threads per triangle (0.25)\n"
    "  --rho     density (default 1)\n"
    "  --gravity gravity vector (default 0,-1,0)\n"
    "  --repeat  runs; the time printed is their median (default 1)\n"
    "  --forces  file for the nodal forces: one line 'fx fy fz' per vertex, in input order\n"
    "  --json    print one JSON object instead of text\n";

struct Args {
  std::string mesh, method = "column", device = "cpu", kernel, forces;
  int grid = 200, repeat = 1;
  double alpha = 0.25, rho = 1.0;
  std::array<double, 3> gravity{0, -1, 0};
  bool json = false;
};

[[noreturn]] void usage_error(const std::string& message) {
  std::cerr << "fluidweight: " << message << "\n" << kUsage;
  std::exit(2);
}

double parse_double(const std::string& flag, const std::string& text) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty()) usage_error(flag + ": '" + text + "' is not a number");
  return v;
}

int parse_int(const std::string& flag, const std::string& text) {
  size_t used = 0;
  int v = 0;
  try {
    v = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty()) usage_error(flag + ": '" + text + "' is not an integer");
  return v;
}

Args parse(int argc, char** argv) {
  Args a;
  for (int k = 1; k < argc; ++k) {
    std::string arg = argv[k], value;
    if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      std::exit(0);
    }
    if (arg.rfind("--", 0) != 0) {
      if (!a.mesh.empty()) usage_error("more than one mesh given ('" + arg + "')");
      a.mesh = arg;
      continue;
    }
    size_t eq = arg.find('=');
    if (eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    }
    if (arg == "--json") {
      a.json = true;
      continue;
    }
    if (eq == std::string::npos) {
      if (k + 1 >= argc) usage_error(arg + " needs a value");
      value = argv[++k];
    }
    if (arg == "--grid") {
      a.grid = parse_int(arg, value);
    } else if (arg == "--method") {
      a.method = value;
    } else if (arg == "--device") {
      a.device = value;
    } else if (arg == "--kernel") {
      a.kernel = value;
    } else if (arg == "--alpha") {
      a.alpha = parse_double(arg, value);
    } else if (arg == "--rho") {
      a.rho = parse_double(arg, value);
    } else if (arg == "--gravity") {
      std::stringstream in(value);
      std::string part;
      int d = 0;
      while (std::getline(in, part, ',')) {
        if (d == 3) usage_error("--gravity needs 3 comma-separated numbers");
        a.gravity[d++] = parse_double(arg, part);
      }
      if (d != 3) usage_error("--gravity needs 3 comma-separated numbers");
    } else if (arg == "--repeat") {
      a.repeat = parse_int(arg, value);
      if (a.repeat < 1) usage_error("--repeat must be at least 1");
    } else if (arg == "--forces") {
      a.forces = value;
    } else {
      usage_error("unknown option '" + arg + "'");
    }
  }
  if (a.mesh.empty()) usage_error("no mesh given");
  return a;
}

fw::Options options_from(const Args& a) {
  fw::Options o;
  o.grid = a.grid;
  o.rho = a.rho;
  o.gravity = a.gravity;
  o.alpha = a.alpha;
  o.method = fw::parse_method(a.method);
  if (a.device == "cpu") {
    if (a.kernel.empty() || a.kernel == "fast") {
      o.implementation = fw::Implementation::cpu_fast;
    } else if (a.kernel == "reference") {
      o.implementation = fw::Implementation::cpu_reference;
    } else {
      throw fw::InputError("--kernel: '" + a.kernel + "' is not a cpu kernel (fast, reference)");
    }
  } else if (a.device == "cuda") {
    o.implementation = fw::Implementation::cuda;
    std::string name = a.kernel.empty() ? "tiled" : a.kernel;
    size_t colon = name.find(':');
    if (colon != std::string::npos) {
      o.precision = fw::parse_precision(name.substr(colon + 1));
      name = name.substr(0, colon);
    }
    o.kernel = fw::parse_kernel(name);
  } else {
    throw fw::InputError("--device: '" + a.device + "' is not one of cpu, cuda");
  }
  return o;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string num(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::string kernel_label(const fw::Options& o) {
  switch (o.implementation) {
    case fw::Implementation::cpu_reference:
      return "reference";
    case fw::Implementation::cpu_fast:  // the fast path is the paper's method's alone
      return o.method == fw::Method::column ? "fast" : "reference";
    default:
      return fw::to_string(o.kernel) + ":" + fw::to_string(o.precision);
  }
}

int run(const Args& a) {
  fw::Options o = options_from(a);
  fw::SurfaceMesh mesh = fw::read_surface(a.mesh);
  fw::check_closed_surface(mesh, a.mesh);
  fw::Context context(o);
  context.set_cavities({mesh});
  std::vector<double> wall, gpu;
  fw::Result r;
  for (int k = 0; k < a.repeat; ++k) {
    r = context.compute().front();
    wall.push_back(r.timings.wall_ms);
    gpu.push_back(r.timings.gpu_ms);
  }
  // The readers keep coordinates within 1e30 and sizes above 1e-30; a density or gravity
  // beyond a double's range can still overflow: an error, not "null" printed with exit 0.
  bool finite = std::isfinite(r.signed_volume) && std::isfinite(r.column_volume) &&
                std::isfinite(r.total_weight);
  for (double f : r.forces) finite = finite && std::isfinite(f);
  if (!finite) {
    std::ostringstream msg;
    msg << a.mesh << ": the volume or the weight is not finite (signed volume " << r.signed_volume
        << ", weight " << r.total_weight << ", rho " << o.rho
        << "): the density, gravity or the surface's size overflow a double";
    throw fw::InputError(msg.str());
  }
  if (!a.forces.empty()) {
    std::ofstream out(a.forces);
    if (!out) throw fw::InputError(a.forces + ": cannot write the forces file");
    char line[96];
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", r.forces[3 * v], r.forces[3 * v + 1],
                    r.forces[3 * v + 2]);
      out << line;
    }
    // A full disk shows only when the buffer is flushed: close first, then ask.
    out.close();
    if (out.fail()) throw fw::InputError(a.forces + ": writing the forces failed");
  }
  const bool on_gpu = o.implementation == fw::Implementation::cuda;
  if (a.json) {
    std::cout << "{\"mesh\": " << json_string(a.mesh) << ", \"triangles\": " << mesh.num_triangles()
              << ", \"vertices\": " << mesh.num_vertices() << ", \"grid\": " << o.grid
              << ", \"method\": " << json_string(a.method)
              << ", \"device\": " << json_string(a.device)
              << ", \"kernel\": " << json_string(kernel_label(o)) << ", \"rho\": " << num(o.rho)
              << ", \"gravity\": [" << num(o.gravity[0]) << ", " << num(o.gravity[1]) << ", "
              << num(o.gravity[2]) << "], \"signed_volume\": " << num(r.signed_volume)
              << ", \"volume\": " << num(r.column_volume)
              << ", \"total_weight\": " << num(r.total_weight)
              << ", \"unmatched_columns\": " << r.unmatched_columns << ", \"repeat\": " << a.repeat
              << ", \"time_ms\": " << num(median(wall))
              << ", \"gpu_time_ms\": " << (on_gpu ? num(median(gpu)) : "null") << "}\n";
  } else {
    std::cout << "mesh           " << a.mesh << " (" << mesh.num_triangles() << " triangles, "
              << mesh.num_vertices() << " vertices)\n"
              << "method         " << a.method << ", grid " << o.grid << " x " << o.grid << ", "
              << a.device << " " << kernel_label(o) << "\n"
              << "signed volume  " << num(r.signed_volume) << "\n"
              << "column volume  " << num(r.column_volume) << "\n"
              << "total weight   " << num(r.total_weight) << "\n"
              << "time           " << num(median(wall)) << " ms (median of " << a.repeat << ")\n";
    if (on_gpu) std::cout << "gpu time       " << num(median(gpu)) << " ms (CUDA events)\n";
    if (r.unmatched_columns) {
      std::cout << "warning        " << r.unmatched_columns
                << " columns had unpaired floors and ceilings\n";
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Args args = parse(argc, argv);
  try {
    return run(args);
  } catch (const fw::InputError& e) {
    std::cerr << "fluidweight: error: " << e.what() << "\n";
    return 1;
  } catch (const fw::DeviceError& e) {
    std::cerr << "fluidweight: cuda error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {  // e.g. out of memory: a message, not an abort
    std::cerr << "fluidweight: error: " << e.what() << "\n";
    return 1;
  }
}
