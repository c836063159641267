// The fluidweight command line: JSON fields against the library, the forces file, errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "support.hpp"

namespace fw = fluidweight;
using namespace fwtest;

namespace {

struct CliRun {
  int status;
  std::string output;  // stdout and stderr
};

CliRun run_cli(const std::string& args) {
  std::string command = std::string(FLUIDWEIGHT_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string out;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) out.append(buffer, n);
  int status = pclose(pipe);
  return {WEXITSTATUS(status), out};
}

// The number after "key": in a one-line JSON object.
double json_number(const std::string& json, const std::string& key) {
  size_t at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no key " << key << " in " << json;
    return NAN;
  }
  return std::stod(json.substr(at + key.size() + 4));
}

std::string write_obj(const SurfaceMesh& m, const std::string& name) {
  std::string path = fwtest::scratch_folder() + name;
  std::ofstream out(path);
  out.precision(17);
  for (int v = 0; v < m.num_vertices(); ++v) {
    out << "v " << m.vertices[3 * v] << " " << m.vertices[3 * v + 1] << " " << m.vertices[3 * v + 2]
        << "\n";
  }
  for (int t = 0; t < m.num_triangles(); ++t) {
    out << "f " << m.triangles[3 * t] + 1 << " " << m.triangles[3 * t + 1] + 1 << " "
        << m.triangles[3 * t + 2] + 1 << "\n";
  }
  return path;
}

}  // namespace

TEST(Cli, JsonAndForcesMatchTheLibrary) {
  SurfaceMesh m = fw::shapes::icosphere(3);
  std::string mesh = write_obj(m, "cli_sphere.obj");
  std::string forces = fwtest::scratch_folder() + "cli_forces.txt";
  CliRun r = run_cli(
      mesh + " --grid 64 --rho 1000 --gravity 0,-9.81,0 --repeat 3 --json --forces " + forces);
  ASSERT_EQ(r.status, 0) << r.output;
  Result expected = fw::compute(m, options(fw::Implementation::cpu_fast, 64));
  EXPECT_EQ(json_number(r.output, "triangles"), m.num_triangles());
  EXPECT_EQ(json_number(r.output, "vertices"), m.num_vertices());
  EXPECT_EQ(json_number(r.output, "grid"), 64);
  EXPECT_DOUBLE_EQ(json_number(r.output, "signed_volume"), expected.signed_volume);
  EXPECT_DOUBLE_EQ(json_number(r.output, "volume"), expected.column_volume);
  EXPECT_NEAR(json_number(r.output, "total_weight"), 1000 * 9.81 * expected.column_volume,
              1e-9 * expected.total_weight);
  EXPECT_GE(json_number(r.output, "time_ms"), 0.0);

  std::ifstream in(forces);
  std::vector<double> f;
  for (double x; in >> x;) f.push_back(x);
  ASSERT_EQ(f.size(), expected.forces.size());
  double sum_y = 0;
  for (size_t k = 0; k < f.size(); ++k) {
    EXPECT_NEAR(f[k], expected.forces[k], 1e-12 * expected.total_weight);
    if (k % 3 == 1) sum_y += f[k];
  }
  EXPECT_NEAR(sum_y, -expected.total_weight, 1e-9 * expected.total_weight);
}

TEST(Cli, MethodsAndKernelsAreSelectable) {
  SurfaceMesh m = e_shape();
  std::string mesh = write_obj(m, "cli_e.obj");
  CliRun ref = run_cli(mesh + " --grid 30 --kernel reference --json");
  CliRun hydro = run_cli(mesh + " --method hydrostatic --gravity 0,0,-2 --json");
  ASSERT_EQ(ref.status, 0) << ref.output;
  ASSERT_EQ(hydro.status, 0) << hydro.output;
  EXPECT_NEAR(json_number(ref.output, "volume"), 51.0, 1e-12);
  EXPECT_NEAR(json_number(hydro.output, "total_weight"), 2 * 51.0, 1e-10);
  CliRun text = run_cli(mesh + " --grid=30");
  EXPECT_NE(text.output.find("column volume  51"), std::string::npos) << text.output;
}

TEST(Cli, ErrorsAreClear) {
  CliRun usage = run_cli("--grid 10");
  EXPECT_EQ(usage.status, 2);
  EXPECT_NE(usage.output.find("no mesh given"), std::string::npos);
  EXPECT_EQ(run_cli("x.obj --frobnicate 3").status, 2);
  EXPECT_EQ(run_cli("x.obj --grid ten").status, 2);

  SurfaceMesh open = octahedron({0, 0, 0}, 1);
  open.triangles.resize(open.triangles.size() - 3);
  CliRun bad = run_cli(write_obj(open, "cli_open.obj"));
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.output.find("not a closed surface: edge ("), std::string::npos) << bad.output;
  // A device that takes no data (a full disk) is an error, not a success.
  CliRun full = run_cli(write_obj(e_shape(), "cli_full.obj") + " --forces /dev/full");
  EXPECT_EQ(full.status, 1) << full.output;
  EXPECT_NE(full.output.find("/dev/full: writing the forces failed"), std::string::npos)
      << full.output;
  CliRun kernel = run_cli(write_obj(e_shape(), "cli_k.obj") + " --device cpu --kernel leveraging");
  EXPECT_EQ(kernel.status, 1);
  EXPECT_NE(kernel.output.find("not a cpu kernel"), std::string::npos);
}

// A density and gravity whose product with the volume overflows printed "null" with exit 0
// (found by fuzzing surfaces with huge coordinates; the readers now refuse those).
TEST(Cli, AWeightBeyondADoubleIsAnError) {
  std::string mesh = write_obj(e_shape(), "cli_overflow.obj");
  CliRun ok = run_cli(mesh + " --rho 1e70 --gravity 0,-1e70,0 --json");
  ASSERT_EQ(ok.status, 0) << ok.output;
  EXPECT_NEAR(json_number(ok.output, "total_weight"), 51e140, 1e-9 * 51e140);
  CliRun bad = run_cli(mesh + " --rho 1e308 --gravity 0,-1e10,0 --json");
  EXPECT_EQ(bad.status, 1) << bad.output;
  EXPECT_EQ(bad.output.rfind(
                "fluidweight: error: " + mesh + ": the volume or the weight is not finite", 0),
            0u)
      << bad.output;
}

// At the readers' bounds (a surface spanning 2e-30, coordinates up to 1e30) the weight is the
// closed form: the E shape's 51 times the cube of the scale (rho = 1, |g| = 1).
TEST(Cli, TheWeightIsRightAtTheBoundsOfSize) {
  SurfaceMesh m = e_shape();
  double extent = 0, largest = 0;
  for (int d = 0; d < 3; ++d) {
    double lo = m.vertices[d], hi = lo;
    for (size_t k = d; k < m.vertices.size(); k += 3) {
      lo = std::min(lo, m.vertices[k]);
      hi = std::max(hi, m.vertices[k]);
      largest = std::max(largest, std::fabs(m.vertices[k]));
    }
    extent = std::max(extent, hi - lo);
  }
  for (double scale : {2e-30 / extent, 0.999e30 / largest}) {
    SurfaceMesh s = m;
    for (double& x : s.vertices) x *= scale;
    CliRun r = run_cli(write_obj(s, "cli_bound.obj") + " --grid 30 --json");
    ASSERT_EQ(r.status, 0) << r.output;
    const double expected = 51.0 * scale * scale * scale;
    EXPECT_NEAR(json_number(r.output, "volume"), expected, 1e-12 * expected);
    EXPECT_NEAR(json_number(r.output, "total_weight"), expected, 1e-9 * expected);
  }
}
