// MessageSink / MessageSource (core/concurrency/message_port.hpp) over a lock-free SpscQueue (core/concurrency/spsc_queue.hpp):
// the producing task holds the sink, the consuming task the source, whether the queue lives in one
// process or in shared memory between processes.
#pragma once

#include <cstddef>

#include "core/concurrency/message_port.hpp"
#include "core/concurrency/spsc_queue.hpp"

namespace rescue {

template <typename T, std::size_t N>
class SpscMessageSink final : public MessageSink<T> {
 public:
  explicit SpscMessageSink(SpscQueue<T, N>& queue) noexcept : queue_(&queue) {}
  bool try_send(const T& message) noexcept override { return queue_->try_push(message); }

 private:
  SpscQueue<T, N>* queue_;
};

template <typename T, std::size_t N>
class SpscMessageSource final : public MessageSource<T> {
 public:
  explicit SpscMessageSource(SpscQueue<T, N>& queue) noexcept : queue_(&queue) {}
  bool try_receive(T& out) noexcept override { return queue_->try_pop(out); }

 private:
  SpscQueue<T, N>* queue_;
};

}  // namespace rescue
