// The .h5's load parts, physical groups and units on the water-filled cylinder, on 1 rank and
// on 2 under mpiexec: cavity_pressure_load does the virtual work 3 p V of a closed cavity,
// fluid_weight_load sums to the liquid's weight of the history and summary.json, and what
// nodal_load holds beside them is the silicone's weight; the group masks are the cavity's
// loaded nodes and the clamped ones; the stress tensors are symmetric and give the von Mises
// field and the principal stresses written beside them. A deck without cavities writes
// neither load part.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../deck/temp_folder.hpp"
#include "../pinned_decks.hpp"
#include "text_file.hpp"

namespace {

using hs::testing::TempFolder;

const std::string kSource = HYDROSOFT_SOURCE_DIR;

using hs::testing::text_of;

// The few reads the checks need, on an open file.
struct H5 {
  hid_t file;
  explicit H5(const std::string& path) : file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {}
  ~H5() { H5Fclose(file); }
  bool has(const std::string& name) const { return H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0; }
  template <class T>
  std::vector<T> read(const std::string& name, hid_t type) const {
    const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(set);
    std::vector<T> values(H5Sget_simple_extent_npoints(space));
    H5Dread(set, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
    H5Sclose(space);
    H5Dclose(set);
    return values;
  }
  std::vector<double> doubles(const std::string& name) const {
    return read<double>(name, H5T_NATIVE_DOUBLE);
  }
  std::vector<int> ints(const std::string& name) const { return read<int>(name, H5T_NATIVE_INT); }
  double number(const std::string& object, const std::string& name) const {
    double value = NAN;
    const hid_t a = H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_DOUBLE, &value);
    H5Aclose(a);
    return value;
  }
  std::string text(const std::string& object, const std::string& name) const {
    if (H5Aexists_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT) <= 0) return "<none>";
    const hid_t a = H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
    const hid_t type = H5Aget_type(a);
    std::string value(H5Tget_size(type), '\0');
    H5Aread(a, type, value.data());
    H5Tclose(type);
    H5Aclose(a);
    return value.substr(0, value.find('\0'));
  }
};

double tet_volume(const std::vector<double>& x, const int64_t* t) {
  double a[3], b[3], c[3];
  for (int d = 0; d < 3; ++d) {
    a[d] = x[3 * t[1] + d] - x[3 * t[0] + d];
    b[d] = x[3 * t[2] + d] - x[3 * t[0] + d];
    c[d] = x[3 * t[3] + d] - x[3 * t[0] + d];
  }
  return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0])) /
         6;
}

// The cylinder of input/cylinder_water.yaml on its coarse P1 mesh (../pinned_decks.hpp), in
// few steps.
void check_cylinder(const std::string& launcher) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "cylinder").string();
  const std::string err = (tmp.path() / "err").string();
  const std::string command =
      launcher + std::string(HYDROSOFT_EXE) + " " + kSource + "/input/cylinder_water.yaml -q " +
      hs_test::coarse_cylinder_args() +
      "--set states[0].steps=2 --set states[1].steps=2 --set output.folder=" + folder +
      " > /dev/null 2> " + err;
  ASSERT_EQ(std::system(command.c_str()), 0) << text_of(err);
  const auto summary = nlohmann::json::parse(text_of(folder + "/summary.json"));
  const H5 h5(folder + "/cylinder_water.h5");
  const auto x = h5.doubles("/mesh/coordinates");
  const auto topology = h5.read<int64_t>("/mesh/topology", H5T_NATIVE_INT64);
  const size_t nodes = x.size() / 3, tets = topology.size() / 4;
  EXPECT_EQ(h5.text("/mesh/coordinates", "units"), "m");
  EXPECT_EQ(h5.text("/mesh/topology", "units"), "1");

  // One volume group: every tetrahedron is in "body".
  const auto volume_group = h5.ints("/mesh/volume_group");
  ASSERT_EQ(volume_group.size(), tets);
  EXPECT_EQ(h5.text("/mesh/volume_group", "names"), "[\"body\"]");
  for (int g : volume_group) EXPECT_EQ(g, 0);
  EXPECT_EQ(h5.text("/mesh/group_cavity", "group"), "cavity");
  const auto cavity = h5.ints("/mesh/group_cavity");
  const auto top = h5.ints("/mesh/group_top");
  ASSERT_EQ(cavity.size(), nodes);
  double silicone = 0;
  for (size_t t = 0; t < tets; ++t) silicone += 1070 * tet_volume(x, &topology[4 * t]);

  const auto pressure = h5.doubles("/history/cavity_cavity_pressure_Pa");
  const auto volume = h5.doubles("/history/cavity_cavity_volume_m3");
  const auto weight = h5.doubles("/history/cavity_cavity_fluid_weight_N");
  EXPECT_EQ(h5.text("/history/cavity_cavity_pressure_Pa", "units"), "Pa");
  EXPECT_EQ(h5.text("/history/cavity_cavity_volume_m3", "units"), "m^3");
  const size_t steps = summary["outputs"].get<size_t>();
  ASSERT_EQ(steps, 4u);
  ASSERT_EQ(pressure.size(), steps);
  for (size_t k = 0; k < steps; ++k) {
    const std::string step = "/step_" + std::to_string(k);
    SCOPED_TRACE(step);
    EXPECT_EQ(h5.text(step, "time_kind"), "state");
    for (const char* field :
         {"displacement", "nodal_load", "cavity_pressure_load", "fluid_weight_load"})
      EXPECT_EQ(h5.text(step + "/" + field, "units"), field[0] == 'd' ? "m" : "N") << field;
    EXPECT_EQ(h5.text(step + "/von_mises", "units"), "Pa");
    // The tensors per tetrahedron: von Mises and the principal stresses are those of the
    // written Cauchy stress, which is symmetric.
    EXPECT_EQ(h5.text(step + "/stress", "units"), "Pa");
    EXPECT_EQ(h5.text(step + "/strain", "units"), "1");
    const auto sigma = h5.doubles(step + "/stress");
    const auto principal = h5.doubles(step + "/principal_stress");
    const auto mises = h5.doubles(step + "/von_mises");
    ASSERT_EQ(sigma.size(), 9 * tets);
    ASSERT_EQ(principal.size(), 3 * tets);
    ASSERT_EQ(h5.doubles(step + "/strain").size(), 9 * tets);
    for (size_t e = 0; e < tets; ++e) {
      const double* s = &sigma[9 * e];
      const double* p = &principal[3 * e];
      const double scale = std::abs(s[0]) + std::abs(s[4]) + std::abs(s[8]) + 1;
      EXPECT_NEAR(s[1], s[3], 1e-12 * scale);
      EXPECT_NEAR(p[0] + p[1] + p[2], s[0] + s[4] + s[8], 1e-12 * scale);
      EXPECT_GE(p[0], p[1]);
      EXPECT_GE(p[1], p[2]);
      const double shear = s[1] * s[1] + s[2] * s[2] + s[5] * s[5];
      const double vm =
          std::sqrt(0.5 * ((s[0] - s[4]) * (s[0] - s[4]) + (s[4] - s[8]) * (s[4] - s[8]) +
                           (s[8] - s[0]) * (s[8] - s[0])) +
                    3 * shear);
      EXPECT_NEAR(mises[e], vm, 1e-12 * scale);
    }
    const auto u = h5.doubles(step + "/displacement");
    const auto load = h5.doubles(step + "/nodal_load");
    const auto fp = h5.doubles(step + "/cavity_pressure_load");
    const auto fw = h5.doubles(step + "/fluid_weight_load");
    ASSERT_EQ(fp.size(), 3 * nodes);
    ASSERT_EQ(fw.size(), 3 * nodes);
    // A uniform pressure p on the closed walls (normals out of the body, into the cavity)
    // does the work sum_a x_a . f_a = -p int x . n da = 3 p V on the deformed positions.
    double work = 0;
    std::array<double, 3> w{0, 0, 0}, rest{0, 0, 0};
    for (size_t i = 0; i < 3 * nodes; ++i) {
      work += (x[i] + u[i]) * fp[i];
      w[i % 3] += fw[i];
      rest[i % 3] += load[i] - fp[i] - fw[i];
    }
    EXPECT_NEAR(work, 3 * pressure[k] * volume[k],
                1e-9 * std::abs(3 * pressure[k] * volume[k]) + 1e-12);
    EXPECT_NEAR(std::hypot(w[0], w[1], w[2]), weight[k], 1e-12 * weight[k]);
    EXPECT_GT(weight[k], 0);
    EXPECT_NEAR(w[0], 0, 1e-9 * weight[k]);  // gravity is -y
    EXPECT_NEAR(w[2], 0, 1e-9 * weight[k]);
    // The rest is the silicone's weight, at the step's load factor (1 from the end of the
    // first state on).
    if (h5.number(step, "time") >= 1) {
      EXPECT_NEAR(rest[1], -9.81 * silicone, 1e-9 * 9.81 * silicone);
      EXPECT_NEAR(rest[0], 0, 1e-9 * 9.81 * silicone);
      EXPECT_NEAR(rest[2], 0, 1e-9 * 9.81 * silicone);
    }
    // The pressure loads exactly the cavity's nodes; the clamped nodes do not move.
    if (pressure[k] != 0)
      for (size_t n = 0; n < nodes; ++n) {
        const bool loaded = fp[3 * n] != 0 || fp[3 * n + 1] != 0 || fp[3 * n + 2] != 0;
        EXPECT_EQ(loaded, cavity[n] == 1) << "node row " << n;
      }
    for (size_t n = 0; n < nodes; ++n)
      if (top[n])
        EXPECT_EQ(std::abs(u[3 * n]) + std::abs(u[3 * n + 1]) + std::abs(u[3 * n + 2]), 0);
  }
  const auto& report = summary["end_of_run"]["cavities"][0];
  EXPECT_EQ(weight.back(), report["fluid_weight_total"].get<double>());
  EXPECT_NEAR(weight.back(), 1000 * 9.81 * report["fluid_weight_volume"].get<double>(),
              1e-9 * weight.back());
  EXPECT_GT(pressure.back(), 0);  // inflated

  const std::string xmf = text_of(folder + "/cylinder_water.xmf");
  EXPECT_NE(xmf.find("<Information Name=\"time_kind\" Value=\"state\"/>"), std::string::npos);
  EXPECT_NE(xmf.find("cylinder_water.h5:/step_3/cavity_pressure_load"), std::string::npos);
  EXPECT_NE(xmf.find("cylinder_water.h5:/step_3/fluid_weight_load"), std::string::npos);
  EXPECT_NE(xmf.find("Name=\"group_cavity\""), std::string::npos);
  if (std::ifstream("/usr/bin/pvpython").good()) {
    const std::string check = "/usr/bin/pvpython " + kSource +
                              "/postprocess/check_xdmf_paraview.py " + folder +
                              "/cylinder_water.xmf > " + err + " 2>&1";
    EXPECT_EQ(std::system(check.c_str()), 0) << text_of(err);
  }
}

TEST(OutputFields, CavityLoadsGroupsAndUnitsOnOneRank) { check_cylinder(""); }

TEST(OutputFields, CavityLoadsGroupsAndUnitsOnTwoRanks) {
  check_cylinder(std::string(HYDROSOFT_MPIEXEC) + " -np 2 ");
}

TEST(OutputFields, ADeckWithoutCavitiesWritesNoLoadParts) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "beam").string();
  const std::string command = std::string(HYDROSOFT_EXE) + " " + kSource +
                              "/input/cantilever_gravity.yaml -q --set mesh.order=1 "
                              "--set time.steps=2 --set output.folder=" +
                              folder + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const H5 h5(folder + "/cantilever_gravity.h5");
  EXPECT_TRUE(h5.has("/step_1/nodal_load"));
  EXPECT_FALSE(h5.has("/step_1/cavity_pressure_load"));
  EXPECT_FALSE(h5.has("/step_1/fluid_weight_load"));
  EXPECT_EQ(h5.text("/step_1", "time_kind"), "load_factor");
  EXPECT_EQ(h5.text("/step_1/J", "units"), "1");
  EXPECT_TRUE(h5.has("/mesh/volume_group"));
}

// A control run's output steps after its loading are target sets, and say so.
TEST(OutputFields, AControlRunLabelsItsStepsAsTargetSets) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "finger").string();
  const std::string command = std::string(HYDROSOFT_EXE) + " " + kSource +
                              "/input/finger_hydraulic.yaml -q " +
                              hs_test::compressible_finger_args() +
                              "--set mesh.parameters.h=0.006 "
                              "--set control.steps_per_target=1 --set output.folder=" +
                              folder + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const auto summary = nlohmann::json::parse(text_of(folder + "/summary.json"));
  const H5 h5(folder + "/finger_hydraulic.h5");
  const int first = summary["targets"][0]["step"].get<int>();
  ASSERT_GT(first, 0);  // the loading to rest comes first
  EXPECT_EQ(h5.text("/step_0", "time_kind"), "state");
  for (const auto& target : summary["targets"])
    EXPECT_EQ(h5.text("/step_" + std::to_string(target["step"].get<int>()), "time_kind"),
              "target_set");
}

// A dynamic run's output steps are physical times, in seconds, and say so: step k at k dt.
TEST(OutputFields, ADynamicRunLabelsItsStepsAsSeconds) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "dynamic").string();
  const std::string command =
      std::string(HYDROSOFT_EXE) + " " + kSource +
      "/input/cantilever_dynamic.yaml -q --set mesh.order=1 --set time.dt=0.1 "
      "--set time.end_time=0.3 --set output.every=1 --set output.folder=" +
      folder + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const auto summary = nlohmann::json::parse(text_of(folder + "/summary.json"));
  const H5 h5(folder + "/cantilever_dynamic.h5");
  const int steps = summary["outputs"].get<int>();
  ASSERT_GE(steps, 3);
  const double first = h5.number("/step_0", "time");
  for (int k = 0; k < steps; ++k) {
    const std::string step = "/step_" + std::to_string(k);
    EXPECT_EQ(h5.text(step, "time_kind"), "time_s") << step;
    EXPECT_NEAR(h5.number(step, "time") - first, 0.1 * k, 1e-12) << step;
  }
  EXPECT_NEAR(h5.number("/step_" + std::to_string(steps - 1), "time"), 0.3, 1e-12);
  const std::string xmf = text_of(folder + "/cantilever_dynamic.xmf");
  EXPECT_NE(xmf.find("<Information Name=\"time_kind\" Value=\"time_s\"/>"), std::string::npos);
}

// input/cantilever_dynamic.yaml as it is (but for an output at every step) resolves the motion it
// shows: the tip face released under its weight sinks to twice its static sag at half the
// first bending mode's period, Euler-Bernoulli's T = 2 pi / (1.8751^2 sqrt(E h^2 / (12 rho
// L^4))), and is back near rest after one. Before, the deck said T = 3.9 s (true at E = 1e6)
// but had E = 1e9, T = 0.124 s, and steps of 0.1 s.
TEST(OutputFields, TheDynamicDeckResolvesItsFirstBendingMode) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "dynamic").string();
  const std::string command = std::string(HYDROSOFT_EXE) + " " + kSource +
                              "/input/cantilever_dynamic.yaml -q --set output.every=1 "
                              "--set output.folder=" +
                              folder + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const double E = 1e9, rho = 1000, g = 9.81, L = 1.0, h = 0.05;  // the deck's
  const double period =
      2 * M_PI / (1.8751 * 1.8751 * std::sqrt(E * h * h / (12 * rho * L * L * L * L)));
  const double sag = 3 * rho * g * L * L * L * L / (2 * E * h * h);  // static, of the centroid
  const auto summary = nlohmann::json::parse(text_of(folder + "/summary.json"));
  const H5 h5(folder + "/cantilever_dynamic.h5");
  const auto x = h5.doubles("/mesh/coordinates");
  std::vector<size_t> tip;  // the nodes of the face x = L
  for (size_t n = 0; 3 * n < x.size(); ++n)
    if (x[3 * n] > L - 1e-9) tip.push_back(n);
  ASSERT_GT(tip.size(), 3u);
  const int steps = summary["outputs"].get<int>();
  double lowest = 0, lowest_time = 0, last = 0, last_time = 0;
  for (int k = 0; k < steps; ++k) {
    const std::string step = "/step_" + std::to_string(k);
    const auto u = h5.doubles(step + "/displacement");
    double w = 0;
    for (size_t n : tip) w += u[3 * n + 2] / tip.size();
    last = w;
    last_time = h5.number(step, "time");
    if (w < lowest) lowest = w, lowest_time = last_time;
  }
  EXPECT_GE(steps, 50) << "steps of T/50 or less";
  EXPECT_NEAR(lowest, -2 * sag, 0.03 * 2 * sag);
  EXPECT_NEAR(lowest_time, period / 2, 0.04 * period);
  EXPECT_GE(last_time, period);
  EXPECT_LT(last_time, 1.1 * period);
  EXPECT_LT(std::abs(last), 0.1 * sag) << "one period on, near rest";
}

}  // namespace
