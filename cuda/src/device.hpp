// The CUDA side as the Context sees it. device.cu implements it when the module is built with
// CUDA; no_device.cpp otherwise (every call throws DeviceError).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cpu.hpp"

namespace fluidweight::detail {

class DeviceBackend {
 public:
  virtual ~DeviceBackend() = default;
  // Uploads the cavities' connectivity and sizes the device buffers.
  virtual void set_cavities(const std::vector<CavityView>& cavities) = 0;
  // Runs the chosen method on the current positions (same connectivity as set_cavities).
  // Fills each cavity's output like the CPU implementations, the signed volumes, and the
  // kernels' time measured with CUDA events.
  virtual void compute(const std::vector<CavityView>& cavities, std::vector<CavityOutput>& out,
                       std::vector<double>& signed_volumes, double& gpu_ms) = 0;
  // Replays the captured kernel graph `repeats` times, each between two events (ms of each).
  virtual std::vector<double> time_replays(int repeats) = 0;
};

// True when built with CUDA and a device is present.
bool device_present();
std::string device_name();

// Throws DeviceError when CUDA is not built in or no device is present.
std::unique_ptr<DeviceBackend> make_device_backend(const Options& options, const Frame& frame);

}  // namespace fluidweight::detail
