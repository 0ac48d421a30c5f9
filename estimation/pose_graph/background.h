#ifndef SPLAM_ESTIMATION_POSE_GRAPH_BACKGROUND_H_
#define SPLAM_ESTIMATION_POSE_GRAPH_BACKGROUND_H_

#include <functional>
#include <future>
#include <memory>
#include <type_traits>

namespace splam::estimation {

// Threads of its own for work that runs beside the caller's (Boost.Asio's thread_pool; the
// graph SLAM's loop search): a task starts on the first free thread and its result comes back
// through a std::future. Starting one costs a few microseconds where std::async starts a thread
// for every task (about 90 us on the 2-core machine under load).
class Background {
 public:
  explicit Background(int threads);
  // Waits for every task started.
  ~Background();
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;

  template <typename F>
  std::future<std::invoke_result_t<F>> Run(F task) {
    using Result = std::invoke_result_t<F>;
    // Shared: Post takes a copyable std::function, and a packaged_task only moves.
    auto packaged = std::make_shared<std::packaged_task<Result()>>(std::move(task));
    std::future<Result> result = packaged->get_future();
    Post([packaged] { (*packaged)(); });
    return result;
  }

 private:
  void Post(std::function<void()> task);
  struct Pool;
  std::unique_ptr<Pool> pool_;
};

}  // namespace splam::estimation

#endif  // SPLAM_ESTIMATION_POSE_GRAPH_BACKGROUND_H_
