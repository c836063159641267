// Floor of a call on this GPU: CUDA events around replays of graphs of 1 to 4 empty kernels,
// and of one kernel of 512 blocks that ends with the last-block (ticket) pattern; then the
// latency of one dependent global load (pointer chase) from L2 and from device memory.
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

__global__ void chase_kernel(const unsigned* next, int steps, unsigned* sink) {
  unsigned p = 0;
  for (int k = 0; k < steps; ++k) p = next[p];
  *sink = p;
}

void chase(size_t bytes) {
  size_t n = bytes / 4;
  std::vector<unsigned> h(n);
  // A random cycle with a stride of at least a few cache lines.
  std::vector<unsigned> order(n / 64);
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<unsigned>(k * 64);
  unsigned seed = 12345;
  for (size_t k = order.size() - 1; k > 0; --k) {
    seed = seed * 1103515245u + 12345u;
    std::swap(order[k], order[seed % (k + 1)]);
  }
  for (size_t k = 0; k < order.size(); ++k) h[order[k]] = order[(k + 1) % order.size()];
  unsigned *d, *sink;
  cudaMalloc(&d, bytes);
  cudaMalloc(&sink, 4);
  cudaMemcpy(d, h.data(), bytes, cudaMemcpyHostToDevice);
  chase_kernel<<<1, 1>>>(d, 1000, sink);
  cudaEvent_t a, b;
  cudaEventCreate(&a);
  cudaEventCreate(&b);
  const int steps = 20000;
  cudaEventRecord(a);
  chase_kernel<<<1, 1>>>(d, steps, sink);
  cudaEventRecord(b);
  cudaEventSynchronize(b);
  float ms;
  cudaEventElapsedTime(&ms, a, b);
  std::printf("dependent load, %7.1f MB buffer: %6.0f ns\n", bytes / 1e6, 1e6 * ms / steps);
  cudaFree(d);
  cudaFree(sink);
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
    const char* names[] = {
        "1 empty kernel",  "2 empty kernels",           "3 empty kernels",
        "4 empty kernels", "ticket kernel, 512 blocks", "ticket kernel, 64 blocks"};
    std::printf("graph of %-28s median %6.2f us  (min %6.2f)\n", names[variant],
                1000 * ms[ms.size() / 2], 1000 * ms[0]);
  }
  for (size_t mb : {1, 16, 256}) chase(mb << 20);
  return 0;
}
