// Shared by the GPU methods: error checks that stop the program with the failing call, and
// the permutation kernels (kernels.cu).
#pragma once

#include <cuda_runtime.h>
#include <cusolver_common.h>

#include <stdexcept>
#include <string>

#define CUDA_CHECK(call)                                                            \
  do {                                                                              \
    cudaError_t e_ = (call);                                                        \
    if (e_ != cudaSuccess)                                                          \
      throw std::runtime_error(std::string(#call) + ": " + cudaGetErrorString(e_)); \
  } while (0)

#define STATUS_CHECK(call)                                                                        \
  do {                                                                                            \
    int s_ = static_cast<int>(call);                                                              \
    if (s_ != 0) throw std::runtime_error(std::string(#call) + ": status " + std::to_string(s_)); \
  } while (0)

// out[k] = in[index[k]], k < count, on the stream: values into a permuted pattern, or a
// vector into a permuted order.
void gather(double* out, const double* in, const int* index, int count, cudaStream_t stream);
// out[index[k]] = in[k]: back from the permuted order.
void scatter(double* out, const double* in, const int* index, int count, cudaStream_t stream);

// A device array that frees itself.
template <class T>
struct DeviceArray {
  T* p = nullptr;
  explicit DeviceArray(size_t count) { CUDA_CHECK(cudaMalloc(&p, count * sizeof(T) + 16)); }
  ~DeviceArray() { cudaFree(p); }
  DeviceArray(const DeviceArray&) = delete;
  DeviceArray& operator=(const DeviceArray&) = delete;
};
