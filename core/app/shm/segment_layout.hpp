// The tasks' shared-memory segment, byte by byte (design brief section 3, paper IV-A,
// docs/shared-memory.md): a self-describing header, then TaskLinks at a fixed offset.
//
//   SegmentHeader (its own layout never changes: any version can read it and say what it found)
//     magic            "RESCUEMS" as a little-endian u64
//     header_size      bytes of this header (TaskLinks starts at kLinksOffset)
//     layout_version   TaskLinks::kLayoutVersion of the creator
//     layout_hash      FNV-1a of the compile-time layout: every TaskLinks member's name, type text,
//                      offset and size, and sizeof(TaskLinks) (from RESCUE_TASK_LINKS_MEMBERS)
//     total_size       bytes of the whole segment
//     creator_pid, creator_start_time   who created it (a reused pid has another start time)
//     ready            kReady once everything above and TaskLinks are written: written last
//
// The layout table, the hash and the byte map of `rescue-motion docs shared-memory` all come from
// the one member list, so they cannot disagree with the record the tasks use.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <type_traits>

#include "core/app/links/task_links.hpp"
#include "core/base/span.hpp"

namespace rescue::app::shm {

constexpr std::uint64_t kMagic = 0x534D'4555'4353'4552ULL;  // "RESCUEMS" in little-endian byte order
constexpr std::uint32_t kReady = 0x5245'4459U;             // "YDER": set last by the creator
constexpr std::uint32_t kNotReady = 0;

struct SegmentHeader {
  std::uint64_t magic;
  std::uint32_t header_size;
  std::uint32_t layout_version;
  std::uint32_t layout_hash;
  std::uint32_t reserved;
  std::uint64_t total_size;
  std::int32_t creator_pid;
  std::uint32_t reserved2;
  std::uint64_t creator_start_time;  // clock ticks since boot, /proc/PID/stat field 22
  std::atomic<std::uint32_t> ready;
  std::uint32_t reserved3;
};
static_assert(std::is_standard_layout_v<SegmentHeader>, "shared between processes: standard layout only");
static_assert(std::atomic<std::uint32_t>::is_always_lock_free, "the ready word must be lock-free");
static_assert(sizeof(SegmentHeader) == 56, "the header's layout never changes");

// The whole segment: header, then the links, page-aligned start of the links not required.
struct SharedSegment {
  SegmentHeader header;
  TaskLinks links;
};
static_assert(std::is_standard_layout_v<SharedSegment>, "shared between processes: standard layout only");

constexpr std::size_t kLinksOffset = offsetof(SharedSegment, links);
constexpr std::size_t kSegmentSize = sizeof(SharedSegment);

// One row of the byte map: a TaskLinks member, offsets relative to the segment's start.
struct LayoutEntry {
  const char* name;
  const char* type;
  const char* who;  // who writes -> who reads
  std::size_t offset;
  std::size_t size;
};

#define RESCUE_SHM_LAYOUT_ROW(member, writers, ...) \
  LayoutEntry{#member, #__VA_ARGS__, writers, kLinksOffset + offsetof(TaskLinks, member), sizeof(TaskLinks::member)},
inline constexpr LayoutEntry kLayout[] = {RESCUE_TASK_LINKS_MEMBERS(RESCUE_SHM_LAYOUT_ROW)};
#undef RESCUE_SHM_LAYOUT_ROW
constexpr std::size_t kLayoutEntries = sizeof(kLayout) / sizeof(kLayout[0]);

namespace detail {
constexpr std::uint32_t kFnvOffset = 2166136261U;
constexpr std::uint32_t kFnvPrime = 16777619U;
constexpr std::uint32_t fnv_text(std::uint32_t h, const char* text) {
  for (std::size_t i = 0; text[i] != '\0'; ++i) h = (h ^ static_cast<std::uint8_t>(text[i])) * kFnvPrime;
  return (h ^ 0U) * kFnvPrime;  // the terminator separates fields
}
constexpr std::uint32_t fnv_number(std::uint32_t h, std::uint64_t value) {
  for (int byte = 0; byte < 8; ++byte) h = (h ^ static_cast<std::uint8_t>(value >> (8 * byte))) * kFnvPrime;
  return h;
}
constexpr std::uint32_t layout_hash() {
  std::uint32_t h = fnv_number(kFnvOffset, sizeof(SegmentHeader));
  h = fnv_number(h, kLinksOffset);
  h = fnv_number(h, sizeof(TaskLinks));
  for (const LayoutEntry& e : kLayout) {
    h = fnv_text(h, e.name);
    h = fnv_text(h, e.type);
    h = fnv_number(h, e.offset);
    h = fnv_number(h, e.size);
  }
  return h;
}
}  // namespace detail

// The hash of this program's layout, computed at compile time.
constexpr std::uint32_t kLayoutHash = detail::layout_hash();

// Writes docs/shared-memory.md's generated part: the header's fields and the byte map of the
// links, one row per member (`rescue-motion docs shared-memory`).
void write_segment_map_markdown(std::FILE* out) noexcept;

}  // namespace rescue::app::shm
