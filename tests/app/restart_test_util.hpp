// Helpers of the tests that start, signal and restart the hydrosoft executable: a child
// process under /bin/sh, polling for a file, and the last output step of an .h5 in mesh
// numbering.
#pragma once

#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "text_file.hpp"

namespace hs::testing {

// Waits (at most 120 s) until `path` exists; false if it never did.
inline bool wait_for_file(const std::string& path) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!std::filesystem::exists(path) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  return std::filesystem::exists(path);
}

// The JSON state of a checkpoint file (its stepping position, sizes, ...); null if the file
// does not open or holds none.
inline nlohmann::json checkpoint_state(const std::string& path) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return nullptr;
  nlohmann::json state;
  const hid_t a = H5Aopen(file, "state", H5P_DEFAULT);
  if (a >= 0) {
    const hid_t type = H5Aget_type(a);
    std::string text(H5Tget_size(type), '\0');
    if (H5Aread(a, type, text.data()) >= 0 && nlohmann::json::accept(text))
      state = nlohmann::json::parse(text);
    H5Tclose(type);
    H5Aclose(a);
  }
  H5Fclose(file);
  return state;
}

// The last step_<k> of an .h5: its displacements placed by /mesh/node_ids (mesh numbering),
// and its time attribute. Empty if the file or a step cannot be read.
struct LastStep {
  std::vector<double> u;
  double time = 0;
  int steps = 0;
};

inline LastStep last_step(const std::string& path) {
  LastStep last;
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return last;
  while (H5Lexists(file, ("/step_" + std::to_string(last.steps)).c_str(), H5P_DEFAULT) > 0)
    ++last.steps;
  if (last.steps > 0) {
    const std::string step = "/step_" + std::to_string(last.steps - 1);
    const hid_t ids_set = H5Dopen2(file, "/mesh/node_ids", H5P_DEFAULT);
    const hid_t space = H5Dget_space(ids_set);
    const hssize_t n = H5Sget_simple_extent_npoints(space);
    std::vector<int64_t> ids(n);
    std::vector<double> u(3 * n);
    H5Dread(ids_set, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, ids.data());
    const hid_t u_set = H5Dopen2(file, (step + "/displacement").c_str(), H5P_DEFAULT);
    H5Dread(u_set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, u.data());
    const hid_t time = H5Aopen_by_name(file, step.c_str(), "time", H5P_DEFAULT, H5P_DEFAULT);
    H5Aread(time, H5T_NATIVE_DOUBLE, &last.time);
    last.u.assign(3 * n, 0.0);
    for (hssize_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) last.u[3 * ids[i] + c] = u[3 * i + c];
    H5Aclose(time);
    H5Dclose(u_set);
    H5Sclose(space);
    H5Dclose(ids_set);
  }
  H5Fclose(file);
  return last;
}

// max |a - b| / max |a|, or -1 when the sizes differ.
inline double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.empty()) return -1;
  double diff = 0, scale = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    diff = std::max(diff, std::abs(a[i] - b[i]));
    scale = std::max(scale, std::abs(a[i]));
  }
  return diff / scale;
}

}  // namespace hs::testing
