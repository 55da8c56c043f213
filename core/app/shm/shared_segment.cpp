#include "core/app/shm/shared_segment.hpp"

#include <unistd.h>

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <new>

namespace rescue::app::shm {
namespace {

constexpr hal::Nanoseconds kAttachPoll = hal::kNsPerMs;
constexpr const char* kLiveOtherLayout = "segment of another layout in use by a live process";

// The creator pid in the header of the segment `name` now (0 when it cannot be read): for a message.
std::int32_t creator_pid_of(const SegmentName& name) noexcept {
  const Result<hal::SharedMemory> existing = hal::SharedMemory::open_existing(name.c_str());
  if (!existing.ok() || existing.value().size() < sizeof(SegmentHeader)) return 0;
  return static_cast<const SegmentHeader*>(existing.value().data())->creator_pid;
}

// Value-initialises the record (atomics, queues, seqlocks) in the zeroed pages of a new segment.
SharedSegment* construct_segment(void* memory) noexcept { return new (memory) SharedSegment(); }

SegmentName name_from(const char* text) noexcept {
  SegmentName name;
  (void)std::snprintf(name.text.data(), name.text.size(), "%s", text);
  return name;
}

// What an existing segment of `name` is: stale (with why) or in use (error busy).
Result<Previous> inspect_existing(const SegmentName& name, hal::ProcessIdentity* creator) noexcept {
  Result<hal::SharedMemory> existing = hal::SharedMemory::open_existing(name.c_str());
  if (!existing.ok()) {
    // Vanished meanwhile, or empty (created but never sized): nothing to trust either way.
    if (existing.error().code == Errc::not_found || existing.error().code == Errc::truncated) return Previous::no_header;
    return existing.error();
  }
  const hal::SharedMemory& memory = existing.value();
  if (memory.size() < sizeof(SegmentHeader)) return Previous::no_header;
  const auto* header = static_cast<const SegmentHeader*>(memory.data());
  if (header->magic != kMagic) return Previous::no_header;
  creator->pid = header->creator_pid;
  creator->start_time = header->creator_start_time;
  if (hal::process_alive(*creator)) {
    // Another program's layout is refused naming both (describe_segment_error): version and hash
    // found here, this program's are its constants. The same layout is a second instance: busy.
    if (header->layout_version != TaskLinks::kLayoutVersion || header->layout_hash != kLayoutHash) {
      return make_error(Errc::version, kLiveOtherLayout, header->layout_version, header->layout_hash);
    }
    return make_error(Errc::busy, "segment in use by a live process", static_cast<std::uint32_t>(creator->pid));
  }
  return Previous::creator_dead;
}

// True when the segment now at `name` is the one whose header is `ours` (same creator pid and start
// time): another program may have put its own segment at the name meanwhile; that one is not ours to
// unlink.
bool name_is_still_ours(const SegmentName& name, const SegmentHeader& ours) noexcept {
  const Result<hal::SharedMemory> existing = hal::SharedMemory::open_existing(name.c_str());
  if (!existing.ok() || existing.value().size() < sizeof(SegmentHeader)) return false;
  const auto* header = static_cast<const SegmentHeader*>(existing.value().data());
  return header->creator_pid == ours.creator_pid && header->creator_start_time == ours.creator_start_time;
}

}  // namespace

SegmentName default_segment_name(const char* state_dir) noexcept {
  std::uint32_t h = detail::kFnvOffset;
  for (const char* p = state_dir; p != nullptr && *p != '\0'; ++p) h = (h ^ static_cast<std::uint8_t>(*p)) * detail::kFnvPrime;
  SegmentName name;
  (void)std::snprintf(name.text.data(), name.text.size(), "/rescue-motion-%08" PRIx32, h);
  return name;
}

Result<SegmentName> segment_name(const char* name) noexcept {
  if (!hal::valid_shared_memory_name(name) || std::strlen(name) >= SegmentName{}.text.size()) {
    return make_error(Errc::invalid_argument, "--segment: a name \"/NAME\" of at most 62 characters without another '/'");
  }
  return name_from(name);
}

const char* to_string(Previous previous) noexcept {
  switch (previous) {
    case Previous::none: return "none";
    case Previous::creator_dead: return "its creator is dead";
    case Previous::no_header: return "it has no valid header";
  }
  return "?";
}

SegmentOwner::~SegmentOwner() { release(); }

SegmentOwner::SegmentOwner(SegmentOwner&& other) noexcept : memory_(std::move(other.memory_)), name_(other.name_) {
  other.name_ = SegmentName{};
}

SegmentOwner& SegmentOwner::operator=(SegmentOwner&& other) noexcept {
  if (this != &other) {
    release();
    memory_ = std::move(other.memory_);
    name_ = other.name_;
    other.name_ = SegmentName{};
  }
  return *this;
}

void SegmentOwner::release() noexcept {
  if (memory_.mapped() && name_.text[0] != '\0' && name_is_still_ours(name_, segment().header)) {
    (void)hal::SharedMemory::unlink(name_.c_str());
  }
  memory_ = hal::SharedMemory{};
  name_ = SegmentName{};
}

void SegmentOwner::forget() noexcept {
  name_ = SegmentName{};
  memory_ = hal::SharedMemory{};
}

Result<SegmentOwner> SegmentOwner::create(const SegmentName& name, CreateReport* report) noexcept {
  CreateReport local;
  CreateReport& out = report != nullptr ? *report : local;
  out = CreateReport{};
  const Result<hal::ProcessIdentity> self = hal::own_process_identity();
  if (!self.ok()) return self.error();

  Result<hal::SharedMemory> memory = hal::SharedMemory::create_exclusive(name.c_str(), kSegmentSize);
  if (!memory.ok() && memory.error().code == Errc::busy) {
    const Result<Previous> previous = inspect_existing(name, &out.previous_creator);
    if (!previous.ok()) return previous.error();
    out.previous = previous.value();
    (void)hal::SharedMemory::unlink(name.c_str());  // stale: replaced, never trusted
    memory = hal::SharedMemory::create_exclusive(name.c_str(), kSegmentSize);
  }
  if (!memory.ok()) return memory.error();

  SegmentOwner owner;
  owner.memory_ = std::move(memory.value());
  owner.name_ = name;
  // The pages read zero (ftruncate): construct the record in place, then the header, ready last.
  SegmentHeader& header = construct_segment(owner.memory_.data())->header;
  header.creator_pid = self.value().pid;
  header.creator_start_time = self.value().start_time;
  header.magic = kMagic;
  header.header_size = sizeof(SegmentHeader);
  header.layout_version = TaskLinks::kLayoutVersion;
  header.layout_hash = kLayoutHash;
  header.total_size = kSegmentSize;
  out.memory_lock = owner.memory_.lock();
  header.ready.store(kReady, std::memory_order_release);
  return owner;
}

Status check_header(const SegmentHeader& header, std::size_t mapped_size) noexcept {
  if (header.magic != kMagic) return make_error(Errc::malformed, "not a rescue-motion segment (magic)");
  if (header.layout_version != TaskLinks::kLayoutVersion) {
    return make_error(Errc::version, "segment layout version differs", header.layout_version, TaskLinks::kLayoutVersion);
  }
  if (header.layout_hash != kLayoutHash) {
    return make_error(Errc::mismatch, "segment layout hash differs", header.layout_hash, kLayoutHash);
  }
  if (header.total_size != kSegmentSize || mapped_size < kSegmentSize) {
    return make_error(Errc::mismatch, "segment size differs", static_cast<std::uint32_t>(mapped_size),
                      static_cast<std::uint32_t>(kSegmentSize));
  }
  return Status::success();
}

Result<SegmentAttachment> SegmentAttachment::attach(const SegmentName& name, hal::Clock& clock,
                                                    hal::Nanoseconds timeout) noexcept {
  const hal::Nanoseconds deadline = clock.now() + timeout;
  SegmentAttachment attachment;
  for (;;) {
    if (!attachment.memory_.mapped()) {
      Result<hal::SharedMemory> opened = hal::SharedMemory::open_existing(name.c_str());
      if (opened.ok() && opened.value().size() >= sizeof(SegmentHeader)) {
        attachment.memory_ = std::move(opened.value());
      } else if (!opened.ok() && opened.error().code != Errc::not_found && opened.error().code != Errc::truncated) {
        return opened.error();
      }
    }
    if (attachment.memory_.mapped()) {
      const SegmentHeader& header = attachment.segment().header;
      if (header.ready.load(std::memory_order_acquire) == kReady) {
        RESCUE_TRY(check_header(header, attachment.memory_.size()));
        return attachment;
      }
    }
    if (clock.now() >= deadline) {
      return make_error(Errc::timeout, "segment not ready within the time limit", attachment.memory_.mapped() ? 1U : 0U);
    }
    clock.sleep_until(clock.now() + kAttachPoll);
  }
}

std::size_t describe_segment_error(const SegmentName& name, const Error& error, char* buffer, std::size_t size) noexcept {
  int n = 0;
  if (error.code == Errc::version && std::strcmp(error.what, "segment layout version differs") == 0) {
    n = std::snprintf(buffer, size, "segment %s: layout version %" PRIu32 " found, this program has %" PRIu32
                      "; refused (stop the other program or use another --segment)",
                      name.c_str(), error.detail0, error.detail1);
  } else if (error.code == Errc::mismatch && std::strcmp(error.what, "segment layout hash differs") == 0) {
    n = std::snprintf(buffer, size, "segment %s: layout hash 0x%08" PRIx32 " found, this program has 0x%08" PRIx32
                      " (same version, another build); refused",
                      name.c_str(), error.detail0, error.detail1);
  } else if (error.code == Errc::mismatch && std::strcmp(error.what, "segment size differs") == 0) {
    n = std::snprintf(buffer, size, "segment %s: %" PRIu32 " bytes found, this program needs %" PRIu32 "; refused",
                      name.c_str(), error.detail0, error.detail1);
  } else if (error.code == Errc::version && std::strcmp(error.what, kLiveOtherLayout) == 0) {
    n = std::snprintf(buffer, size, "segment %s: layout version %" PRIu32 " hash 0x%08" PRIx32 " of running pid %d, "
                      "this program has version %" PRIu32 " hash 0x%08" PRIx32
                      "; refused, left as it is (stop that program or use another --segment)",
                      name.c_str(), error.detail0, error.detail1, static_cast<int>(creator_pid_of(name)),
                      TaskLinks::kLayoutVersion, kLayoutHash);
  } else if (error.code == Errc::busy) {
    n = std::snprintf(buffer, size, "segment %s is in use by a running process (pid %" PRIu32 "); not replaced",
                      name.c_str(), error.detail0);
  } else if (error.code == Errc::permission_denied && std::strcmp(error.what, hal::kForeignSegment) == 0) {
    n = std::snprintf(buffer, size, "segment %s is owned by uid %" PRIu32 ", not ours (uid %u); refused, left as it is "
                      "(remove it as that user or root: rm /dev/shm%s; or use another --segment)",
                      name.c_str(), error.detail0, static_cast<unsigned>(::geteuid()), name.c_str());
  } else if (error.code == Errc::timeout) {
    n = std::snprintf(buffer, size, "segment %s: %s (%s)", name.c_str(), error.what,
                      error.detail0 != 0 ? "it exists but its ready word is not set" : "no segment of that name");
  } else {
    n = std::snprintf(buffer, size, "segment %s: %s (%s, detail %" PRIu32 ")", name.c_str(), error.what,
                      to_string(error.code), error.detail0);
  }
  return n < 0 ? 0 : static_cast<std::size_t>(n);
}

}  // namespace rescue::app::shm
