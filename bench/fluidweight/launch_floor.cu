// Floor of a call on this GPU: CUDA events around replays of graphs of 1 to 4 empty kernels,
// and of one kernel of 512 blocks that ends with the last-block (ticket) pattern.
// Build: nvcc -O3 -arch=sm_90 launch_floor.cu -o launch_floor
#include <algorithm>
#include <cstdio>
#include <vector>

__global__ void empty_kernel() {}

__global__ void ticket_kernel(unsigned* ticket, double* partials, double* out) {
  __shared__ bool last;
  if (threadIdx.x == 0) {
    partials[blockIdx.x] = blockIdx.x;
    __threadfence();
    last = atomicAdd(ticket, 1u) == gridDim.x - 1;
  }
  __syncthreads();
  if (last && threadIdx.x == 0) {
    double s = 0;
    for (unsigned k = 0; k < gridDim.x; ++k) s += partials[k];
    *out = s;
    *ticket = 0;
  }
}

int main() {
  cudaStream_t stream;
  cudaStreamCreate(&stream);
  unsigned* ticket;
  double *partials, *out;
  cudaMalloc(&ticket, 4);
  cudaMemset(ticket, 0, 4);
  cudaMalloc(&partials, 8 * 4096);
  cudaMalloc(&out, 8);
  cudaEvent_t a, b;
  cudaEventCreate(&a);
  cudaEventCreate(&b);
  for (int variant = 0; variant < 6; ++variant) {
    cudaGraph_t graph;
    cudaGraphExec_t exec;
    cudaStreamBeginCapture(stream, cudaStreamCaptureModeThreadLocal);
    if (variant < 4) {
      for (int k = 0; k <= variant; ++k) empty_kernel<<<1, 32, 0, stream>>>();
    } else {
      int blocks = variant == 4 ? 512 : 64;
      ticket_kernel<<<blocks, 256, 0, stream>>>(ticket, partials, out);
    }
    cudaStreamEndCapture(stream, &graph);
    cudaGraphInstantiate(&exec, graph, 0);
    std::vector<float> ms;
    for (int r = 0; r < 200; ++r) {
      cudaEventRecord(a, stream);
      cudaGraphLaunch(exec, stream);
      cudaEventRecord(b, stream);
      cudaEventSynchronize(b);
      float t;
      cudaEventElapsedTime(&t, a, b);
      if (r >= 20) ms.push_back(t);
    }
    std::sort(ms.begin(), ms.end());
    const char* names[] = {"1 empty kernel", "2 empty kernels", "3 empty kernels",
                           "4 empty kernels", "ticket kernel, 512 blocks", "ticket kernel, 64 blocks"};
    std::printf("graph of %-28s median %6.2f us  (min %6.2f)\n", names[variant],
                1000 * ms[ms.size() / 2], 1000 * ms[0]);
  }
  return 0;
}
