// Host-side helpers of the CUDA backend: error checks, device arrays that only grow, page-locked
// host arrays.
#pragma once

#include <cuda_runtime.h>

#include <algorithm>
#include <string>
#include <vector>

#include "fluidweight/fluidweight.hpp"

namespace fluidweight::detail {

inline void check(cudaError_t status, const char* what) {
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

inline int next_power_of_two(int x) {
  int p = 1;
  while (p < x) p <<= 1;
  return p;
}

}  // namespace fluidweight::detail
