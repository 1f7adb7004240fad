// The shader as an asynchronous service for the frame loop: batches go in, finished results
// come out whenever the caller asks, and the caller never waits for shading.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <tbb/task_arena.h>

#include "shade/shader.h"

namespace epi {

class AsyncShader {
 public:
  // threads: TBB concurrency of the shading worker (0: all cores). A batch is shaded in
  // slices of slice_size requests, so results trickle out while a large batch runs.
  // before_slice (tests): runs on the shading thread, without locks, before each slice is taken;
  // a test holds the shader by blocking in it.
  explicit AsyncShader(const Shader& shader, int threads = 0, size_t slice_size = 1024,
                       std::function<void()> before_slice = {});
  ~AsyncShader();  // drops pending work, finishes the slice in flight, joins
  AsyncShader(const AsyncShader&) = delete;
  AsyncShader& operator=(const AsyncShader&) = delete;

  // Queues requests made for view; returns at once. Throws std::invalid_argument for an
  // unusable view (see ViewFrame).
  void submit(const View& view, std::vector<ShadeRequest> requests);
  // Appends every finished result (with its triples) to out; returns how many. Never waits
  // for shading: holds a lock only to swap a queue.
  size_t take_results(ShadeBatch& out);
  // Runs update on the worker between two slices, when nothing traces (e.g. moving an
  // object with RayScene::set_object_transform), before any request not yet started. Returns at
  // once, with the id of the first request not yet started of each queued batch (in queue
  // order): those requests, and the ones after them in their batches, will be traced after the
  // update; every earlier one before it.
  std::vector<uint32_t> run_between_batches(std::function<void()> update);
  // Drops requests not yet started; returns how many were dropped.
  size_t cancel_pending();
  // Blocks until everything submitted is shaded (tests, --sync mode).
  void wait_idle();
  size_t pending_requests() const;

 private:
  struct Job {
    ViewFrame frame;
    std::vector<ShadeRequest> requests;
    size_t next = 0;  // first request not yet started
  };
  void run();

  const Shader& shader_;
  size_t slice_size_;
  std::function<void()> before_slice_;
  std::unique_ptr<tbb::task_arena> arena_;
  mutable std::mutex mutex_;
  std::condition_variable work_ready_, idle_;
  std::deque<Job> jobs_;
  std::vector<std::function<void()>> updates_;
  size_t pending_ = 0;
  bool busy_ = false, stopping_ = false;
  std::mutex done_mutex_;
  ShadeBatch done_;
  std::thread worker_;
};

}  // namespace epi
