// The two ends of a bounded, non-blocking message queue between tasks, as interfaces: a task sees
// only "try to send" and "try to receive", so the same task code runs against the lock-free SPSC queues
// of shared memory (process mode), in-process queues (thread mode) or a test's fake. Both calls return
// at once: false means "full" (send) or "empty" (receive), never "wait".
#pragma once

namespace rescue {

template <typename T>
class MessageSink {
 public:
  MessageSink() = default;
  MessageSink(const MessageSink&) = delete;
  MessageSink& operator=(const MessageSink&) = delete;
  MessageSink(MessageSink&&) = delete;
  MessageSink& operator=(MessageSink&&) = delete;
  virtual ~MessageSink() = default;
  // Queues a copy of `message`; false when the queue is full (the caller keeps it and retries).
  virtual bool try_send(const T& message) noexcept = 0;
};

template <typename T>
class MessageSource {
 public:
  MessageSource() = default;
  MessageSource(const MessageSource&) = delete;
  MessageSource& operator=(const MessageSource&) = delete;
  MessageSource(MessageSource&&) = delete;
  MessageSource& operator=(MessageSource&&) = delete;
  virtual ~MessageSource() = default;
  // Takes the oldest message into `out`; false when there is none.
  virtual bool try_receive(T& out) noexcept = 0;
};

}  // namespace rescue
