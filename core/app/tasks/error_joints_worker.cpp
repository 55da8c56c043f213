#include "core/app/tasks/error_joints_worker.hpp"

#include <type_traits>

namespace rescue::app {

static_assert(std::is_trivially_copyable_v<ErrorJointsSaveRequest>, "copied through an SpscQueue");
static_assert(std::is_trivially_copyable_v<ErrorJointsSaveResult>, "copied through an SpscQueue");

ErrorJointsSaveRequest ErrorJointsSaveRequest::of(const ErrorJointsContents& contents) noexcept {
  ErrorJointsSaveRequest r;
  r.sequence = contents.sequence;
  for (const LostJointRecord& record : contents.records) r.records[r.count++] = record;  // at most kJointCount
  return r;
}

ErrorJointsContents ErrorJointsSaveRequest::contents() const noexcept {
  ErrorJointsContents c;
  c.sequence = sequence;
  for (std::size_t i = 0; i < count && i < records.size(); ++i) (void)c.records.push_back(records[i]);
  return c;
}

bool ErrorJointsStorageWorker::serve_one() noexcept {
  if (holding_) {
    if (!results_.try_send(held_)) return false;  // the joint manager reads it on its next period
    holding_ = false;
    return true;
  }
  ErrorJointsSaveRequest request;
  if (!requests_.try_receive(request)) return false;
  const Status saved = storage_.save(request.contents());
  ++saves_;
  ErrorJointsSaveResult result;
  result.sequence = request.sequence;
  if (!saved.ok()) {
    ++failures_;
    result.error = saved.error();
  }
  if (!results_.try_send(result)) {
    held_ = result;
    holding_ = true;
    ++results_deferred_;
  }
  return true;
}

}  // namespace rescue::app
