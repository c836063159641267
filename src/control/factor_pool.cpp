#include "control/factor_pool.hpp"

#include <chrono>

namespace hs {

FactorPool::FactorPool(int threads) {
  for (int t = 0; t < threads; ++t) workers_.emplace_back([this] { work(); });
}

FactorPool::~FactorPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  job_ready_.notify_all();
  for (auto& w : workers_) w.join();
}

bool FactorPool::idle() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return in_flight_ < threads();
}

bool FactorPool::submit(CsrMatrix& A, int state) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (in_flight_ >= threads()) return false;
    ++in_flight_;
    jobs_.push_back({std::move(A), state});
  }
  job_ready_.notify_one();
  return true;
}

std::vector<FactorResult> FactorPool::take_finished() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<FactorResult> out = std::move(finished_);
  finished_.clear();
  return out;
}

void FactorPool::wait_idle() {
  std::unique_lock<std::mutex> lock(mutex_);
  job_done_.wait(lock, [this] { return in_flight_ == 0; });
}

void FactorPool::work() {
  CholeskyAnalysis analysis;  // this thread's own: the pattern is analysed once per thread
  for (;;) {
    Job job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      job_ready_.wait(lock, [this] { return stopping_ || !jobs_.empty(); });
      if (jobs_.empty()) return;  // stopping, nothing left
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    FactorResult result;
    result.state = job.state;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      result.factor = analysis.factor(job.matrix, &result.error);
    } catch (const std::exception& e) {
      result.error = e.what();
    }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      finished_.push_back(std::move(result));
      --in_flight_;
    }
    job_done_.notify_all();
  }
}

}  // namespace hs
