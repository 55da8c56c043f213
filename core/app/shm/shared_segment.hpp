// The protocol of the tasks' shared-memory segment (docs/shared-memory.md):
//
//   create   The supervisor (the parent of the task processes, or the one process of --threads)
//            creates the segment exclusively, constructs the header and TaskLinks, and writes the
//            ready word LAST (release). It owns the name: SegmentOwner unlinks it when it goes.
//   stale    A segment of that name that already exists is inspected, never trusted: when its
//            creator (pid AND /proc start time) is dead, or it has no valid header, it is unlinked
//            and created anew (CreateReport says so: the caller logs one line). When its creator
//            still runs, create refuses and touches nothing: busy (detail0 = that pid) when it has
//            this program's layout (a second instance), else version "segment of another layout in
//            use by a live process" (detail0/detail1 = its layout version/hash; the message names
//            both, this program's and the pid).
//   attach   A task process opens the name, waits (bounded, on the clock interface) for the ready
//            word (acquire), then checks magic, layout version, layout hash and size: another
//            version or hash is refused with both values (describe_segment_error).
//
// Errors are values; nothing here allocates.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/app/shm/segment_layout.hpp"
#include "core/base/result.hpp"
#include "hal/proc/process_identity.hpp"
#include "hal/shm/shared_memory.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app::shm {

struct SegmentName {
  std::array<char, 64> text{};
  const char* c_str() const noexcept { return text.data(); }
};

// The default name of an instance: "/rescue-motion-" and 8 hex digits of the FNV-1a hash of its
// state directory's path (one running instance per state directory: hal/files/instance_lock.hpp,
// so one segment per instance).
SegmentName default_segment_name(const char* state_dir) noexcept;
// `--segment NAME`: NAME as given. Errors: invalid_argument when it is not a valid shm_open name.
Result<SegmentName> segment_name(const char* name) noexcept;

// What create found under the name before it created the segment.
enum class Previous : std::uint8_t {
  none,            // the name was free
  creator_dead,    // a segment whose creator no longer runs (pid gone, or reused: start time differs)
  no_header,       // a segment too small for a header, or not marked ready, or another magic
};
const char* to_string(Previous previous) noexcept;

struct CreateReport {
  Previous previous{Previous::none};
  hal::ProcessIdentity previous_creator{};  // when the previous segment had a header
  Status memory_lock{};                      // mlock of the segment (refused without privilege)
};

// Owns the segment: created by create(), unlinked (and unmapped) when destroyed; the name is unlinked
// only while it still names this segment (same creator pid and start time in the header found there),
// so a segment another program put at the name meanwhile is left as it is.
class SegmentOwner {
 public:
  SegmentOwner() = default;
  ~SegmentOwner();
  SegmentOwner(const SegmentOwner&) = delete;
  SegmentOwner& operator=(const SegmentOwner&) = delete;
  SegmentOwner(SegmentOwner&& other) noexcept;
  SegmentOwner& operator=(SegmentOwner&& other) noexcept;

  // Errors: invalid_argument (name), busy "segment in use by a live process" (detail0 = its pid),
  // the OS errors of hal::SharedMemory.
  static Result<SegmentOwner> create(const SegmentName& name, CreateReport* report) noexcept;

  SharedSegment& segment() const noexcept { return *static_cast<SharedSegment*>(memory_.data()); }
  TaskLinks& links() const noexcept { return segment().links; }
  const SegmentName& name() const noexcept { return name_; }
  bool created() const noexcept { return memory_.mapped(); }

 private:
  void release() noexcept;

  hal::SharedMemory memory_;
  SegmentName name_{};
};

// A process's attachment to a segment another process created.
class SegmentAttachment {
 public:
  // Waits up to `timeout` (on `clock`, polling every millisecond) for the name to exist and be
  // ready. Errors: timeout "segment not ready within the time limit" (detail0 = 1 when the name
  // exists), version "segment layout version differs" (detail0 = found, detail1 = this program's),
  // mismatch "segment layout hash differs" (detail0 = found, detail1 = this program's), mismatch
  // "segment size differs" (detail0 = found, detail1 = expected), malformed "not a rescue-motion
  // segment (magic)", the OS errors of hal::SharedMemory.
  static Result<SegmentAttachment> attach(const SegmentName& name, hal::Clock& clock, hal::Nanoseconds timeout) noexcept;

  SharedSegment& segment() const noexcept { return *static_cast<SharedSegment*>(memory_.data()); }
  TaskLinks& links() const noexcept { return segment().links; }

 private:
  hal::SharedMemory memory_;
};

// Checks a mapped, ready header against this program (the checks of attach after the wait).
Status check_header(const SegmentHeader& header, std::size_t mapped_size) noexcept;

// One line for an error of create/attach/check_header, naming both values of a mismatch, e.g.
// "segment /rescue-motion-1a2b3c4d: layout version 2 found, this program has 3".
std::size_t describe_segment_error(const SegmentName& name, const Error& error, char* buffer, std::size_t size) noexcept;

}  // namespace rescue::app::shm
