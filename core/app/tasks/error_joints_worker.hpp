// The error-joints storage worker (docs/joint-manager.md, "The storage worker"): the durable write of
// the error-joints file runs here, on a thread at normal priority, never on the joint manager's period.
// The joint manager sends the whole file's contents as one request on a bounded queue and goes on
// with its period (limits, state machine, reports); the worker saves it (temporary file, fsync, rename,
// fsync of the directory: hal::write_file_atomically) and answers with the outcome on a second bounded
// queue. The joint manager completes reconfiguration steps 3-4 and operator clears when the answer
// says the write is durable.
//
// Nothing is dropped: the joint manager has at most one request in flight (a later change waits for
// the answer, then goes out as the next request with every change so far), and the worker keeps an
// answer the full queue could not take and resends it before it takes another request.
#pragma once

#include <array>
#include <cstdint>

#include "core/app/tasks/error_joints_storage.hpp"
#include "core/base/result.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/robot/error_joints_file.hpp"

namespace rescue::app {

// Joint manager -> worker: the file's complete new contents (a plain record: copied through a queue).
struct ErrorJointsSaveRequest {
  std::uint64_t sequence{0};
  std::uint8_t count{0};
  std::array<LostJointRecord, kJointCount> records{};

  static ErrorJointsSaveRequest of(const ErrorJointsContents& contents) noexcept;
  ErrorJointsContents contents() const noexcept;
};

// Worker -> joint manager: what became of the request of `sequence`.
struct ErrorJointsSaveResult {
  std::uint64_t sequence{0};
  Error error{};  // code ok: the file holds the request's contents durably; else the old file stands
};

class ErrorJointsStorageWorker {
 public:
  ErrorJointsStorageWorker(MessageSource<ErrorJointsSaveRequest>& requests, MessageSink<ErrorJointsSaveResult>& results,
                           ErrorJointsStorage& storage) noexcept
      : requests_(requests), results_(results), storage_(storage) {}

  // Sends a held answer, else takes one request, saves it (this waits for the disk) and answers.
  // Returns whether it did anything (false: nothing to do; the caller may sleep).
  bool serve_one() noexcept;
  // An answer is waiting for room in the results queue.
  bool holding() const noexcept { return holding_; }

  std::uint64_t saves() const noexcept { return saves_; }
  std::uint64_t failures() const noexcept { return failures_; }
  std::uint64_t results_deferred() const noexcept { return results_deferred_; }

 private:
  MessageSource<ErrorJointsSaveRequest>& requests_;
  MessageSink<ErrorJointsSaveResult>& results_;
  ErrorJointsStorage& storage_;
  ErrorJointsSaveResult held_{};
  bool holding_{false};
  std::uint64_t saves_{0};
  std::uint64_t failures_{0};
  std::uint64_t results_deferred_{0};
};

}  // namespace rescue::app
