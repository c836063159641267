// Built without CUDA: the CUDA implementation is refused with a clear error.
#include "device.hpp"

namespace fluidweight::detail {

bool device_present() { return false; }

std::string device_name() { return ""; }

std::unique_ptr<DeviceBackend> make_device_backend(const Options&, const Frame&) {
  throw DeviceError(
      "cuda: this build of the fluid-weight module has no CUDA support (the CUDA toolkit was "
      "not found when it was configured); use the cpu implementation");
}

}  // namespace fluidweight::detail
