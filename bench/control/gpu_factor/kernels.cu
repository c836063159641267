#include "gpu.hpp"

namespace {

__global__ void gather_kernel(double* out, const double* in, const int* index, int count) {
  int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < count) out[k] = in[index[k]];
}

__global__ void scatter_kernel(double* out, const double* in, const int* index, int count) {
  int k = blockIdx.x * blockDim.x + threadIdx.x;
  if (k < count) out[index[k]] = in[k];
}

}  // namespace

void gather(double* out, const double* in, const int* index, int count, cudaStream_t stream) {
  gather_kernel<<<(count + 255) / 256, 256, 0, stream>>>(out, in, index, count);
  CUDA_CHECK(cudaGetLastError());
}

void scatter(double* out, const double* in, const int* index, int count, cudaStream_t stream) {
  scatter_kernel<<<(count + 255) / 256, 256, 0, stream>>>(out, in, index, count);
  CUDA_CHECK(cudaGetLastError());
}
