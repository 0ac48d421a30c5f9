#include "estimation/pose_graph/background.h"

#include <boost/asio/post.hpp>
#include <boost/asio/thread_pool.hpp>

namespace splam::estimation {

struct Background::Pool {
  explicit Pool(int threads) : pool(static_cast<std::size_t>(threads)) {}
  boost::asio::thread_pool pool;
};

Background::Background(int threads) : pool_(std::make_unique<Pool>(threads)) {}

// join() without stop(): the threads end once no task is left.
Background::~Background() { pool_->pool.join(); }

void Background::Post(std::function<void()> task) {
  boost::asio::post(pool_->pool, std::move(task));
}

}  // namespace splam::estimation
