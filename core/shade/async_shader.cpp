#include "shade/async_shader.h"

#include <tbb/task_arena.h>

namespace epi {

AsyncShader::AsyncShader(const Shader& shader, int threads, size_t slice_size, std::function<void()> before_slice)
    : shader_(shader),
      slice_size_(std::max<size_t>(slice_size, 1)),
      before_slice_(std::move(before_slice)),
      arena_(std::make_unique<tbb::task_arena>(threads > 0 ? threads : int(tbb::task_arena::automatic))),
      worker_([this] { run(); }) {}

AsyncShader::~AsyncShader() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    jobs_.clear();  // the slice in flight finishes; its results are dropped with this object
  }
  work_ready_.notify_all();
  worker_.join();
}

void AsyncShader::submit(const View& view, std::vector<ShadeRequest> requests) {
  if (requests.empty()) return;
  ViewFrame frame(view);  // validates the view on the caller's thread
  {
    std::lock_guard lock(mutex_);
    pending_ += requests.size();
    jobs_.push_back(Job{frame, std::move(requests), 0});
  }
  work_ready_.notify_one();
}

std::vector<uint32_t> AsyncShader::run_between_batches(std::function<void()> update) {
  std::vector<uint32_t> unstarted;
  {
    std::lock_guard lock(mutex_);  // the worker takes no slice meanwhile, and takes updates first
    updates_.push_back(std::move(update));
    for (const Job& job : jobs_)
      if (job.next < job.requests.size()) unstarted.push_back(job.requests[job.next].id);
  }
  work_ready_.notify_one();
  return unstarted;
}

size_t AsyncShader::take_results(ShadeBatch& out) {
  ShadeBatch finished;
  {
    std::lock_guard lock(done_mutex_);
    std::swap(finished, done_);
  }
  uint32_t offset = uint32_t(out.triples.size());
  for (ShadeResult& r : finished.results) r.triple_begin += offset;
  out.results.insert(out.results.end(), finished.results.begin(), finished.results.end());
  out.triples.insert(out.triples.end(), finished.triples.begin(), finished.triples.end());
  out.rays += finished.rays;
  return finished.results.size();
}

size_t AsyncShader::cancel_pending() {
  std::lock_guard lock(mutex_);
  size_t dropped = 0;
  for (const Job& job : jobs_) dropped += job.requests.size() - job.next;
  jobs_.clear();
  pending_ -= dropped;
  if (pending_ == 0 && !busy_ && updates_.empty()) idle_.notify_all();
  return dropped;
}

void AsyncShader::wait_idle() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [this] { return pending_ == 0 && !busy_ && updates_.empty(); });
}

size_t AsyncShader::pending_requests() const {
  std::lock_guard lock(mutex_);
  return pending_;
}

void AsyncShader::run() {
  std::unique_lock lock(mutex_);
  bool gate_passed = false;  // before_slice_ ran for the next slice
  while (true) {
    work_ready_.wait(lock, [this] { return stopping_ || !jobs_.empty() || !updates_.empty(); });
    if (stopping_) return;
    busy_ = true;
    if (!updates_.empty()) {
      std::vector<std::function<void()>> updates;
      std::swap(updates, updates_);
      lock.unlock();
      for (auto& update : updates) update();
      lock.lock();
    } else if (before_slice_ && !gate_passed) {
      // The test hook; then back to the top: updates queued meanwhile run before the slice.
      lock.unlock();
      before_slice_();
      lock.lock();
      gate_passed = true;
    } else {
      gate_passed = false;
      // Take one slice off the front job.
      Job& job = jobs_.front();
      const ViewFrame frame = job.frame;
      const size_t begin = job.next, end = std::min(job.requests.size(), begin + slice_size_);
      std::vector<ShadeRequest> slice(job.requests.begin() + std::ptrdiff_t(begin), job.requests.begin() + std::ptrdiff_t(end));
      job.next = end;
      if (job.next == job.requests.size()) jobs_.pop_front();
      lock.unlock();
      ShadeBatch batch;
      arena_->execute([&] { shader_.shade(frame, slice, batch); });
      {
        std::lock_guard done_lock(done_mutex_);
        uint32_t offset = uint32_t(done_.triples.size());
        for (ShadeResult& r : batch.results) r.triple_begin += offset;
        done_.results.insert(done_.results.end(), batch.results.begin(), batch.results.end());
        done_.triples.insert(done_.triples.end(), batch.triples.begin(), batch.triples.end());
        done_.rays += batch.rays;
      }
      lock.lock();
      pending_ -= slice.size();
    }
    busy_ = false;
    if (pending_ == 0 && updates_.empty()) idle_.notify_all();
  }
}

}  // namespace epi
