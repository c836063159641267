// A fixed set of worker threads that run one function together and wait for each other: the
// CPU fast path keeps one between calls so that a control loop does not start threads every
// step.
#pragma once

#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace fluidweight::detail {

class ThreadPool {
 public:
  // `threads` in all, the calling thread included (0: all hardware threads).
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return static_cast<int>(workers_.size()) + 1; }
  // Runs task(thread_index) on every thread, index 0 on the caller, and returns when all end.
  void run(const std::function<void(int)>& task);

 private:
  void work(int index);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  const std::function<void(int)>* task_ = nullptr;
  long generation_ = 0;
  int running_ = 0;
  bool stop_ = false;
};

}  // namespace fluidweight::detail
