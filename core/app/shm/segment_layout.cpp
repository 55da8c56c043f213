#include "core/app/shm/segment_layout.hpp"

#include <cinttypes>

namespace rescue::app::shm {
namespace {

struct HeaderField {
  const char* name;
  const char* type;
  std::size_t offset;
  std::size_t size;
  const char* meaning;
};

#define RESCUE_SHM_HEADER_FIELD(field, type, meaning) \
  HeaderField{#field, type, offsetof(SegmentHeader, field), sizeof(SegmentHeader::field), meaning}
constexpr HeaderField kHeaderFields[] = {
    RESCUE_SHM_HEADER_FIELD(magic, "u64", "\"RESCUEMS\" (0x534d455543534552)"),
    RESCUE_SHM_HEADER_FIELD(header_size, "u32", "bytes of this header"),
    RESCUE_SHM_HEADER_FIELD(layout_version, "u32", "TaskLinks::kLayoutVersion of the creator"),
    RESCUE_SHM_HEADER_FIELD(layout_hash, "u32", "FNV-1a of every member's name, type, offset and size"),
    RESCUE_SHM_HEADER_FIELD(reserved, "u32", "0"),
    RESCUE_SHM_HEADER_FIELD(total_size, "u64", "bytes of the whole segment"),
    RESCUE_SHM_HEADER_FIELD(creator_pid, "i32", "pid of the creator (the supervisor)"),
    RESCUE_SHM_HEADER_FIELD(reserved2, "u32", "0"),
    RESCUE_SHM_HEADER_FIELD(creator_start_time, "u64", "the creator's start time, /proc/PID/stat field 22 (ticks since boot)"),
    RESCUE_SHM_HEADER_FIELD(ready, "atomic u32", "0x52454459 once everything else is written (written last)"),
    RESCUE_SHM_HEADER_FIELD(reserved3, "u32", "0"),
};
#undef RESCUE_SHM_HEADER_FIELD

}  // namespace

void write_segment_map_markdown(std::FILE* out) noexcept {
  (void)std::fprintf(out, "Layout version %" PRIu32 ", layout hash 0x%08" PRIx32 ", segment size %zu bytes (header %zu, "
                          "TaskLinks %zu at offset %zu). Offsets and sizes in bytes, host byte order (x86-64, aarch64: "
                          "little-endian).\n\n",
                     TaskLinks::kLayoutVersion, kLayoutHash, kSegmentSize, sizeof(SegmentHeader), sizeof(TaskLinks),
                     kLinksOffset);
  (void)std::fprintf(out, "### Header\n\n| offset | size | field | type | meaning |\n|---:|---:|---|---|---|\n");
  for (const HeaderField& f : kHeaderFields) {
    (void)std::fprintf(out, "| %zu | %zu | `%s` | %s | %s |\n", f.offset, f.size, f.name, f.type, f.meaning);
  }
  (void)std::fprintf(out, "\n### TaskLinks\n\n| offset | size | member | type | writer -> readers |\n|---:|---:|---|---|---|\n");
  for (const LayoutEntry& e : kLayout) {
    (void)std::fprintf(out, "| %zu | %zu | `%s` | `%s` | %s |\n", e.offset, e.size, e.name, e.type, e.who);
  }
}

}  // namespace rescue::app::shm
