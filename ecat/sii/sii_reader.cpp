#include "ecat/sii/sii_reader.hpp"

#include <algorithm>
#include <cstring>

#include "ecat/codec/registers.hpp"
#include "ecat/sii/sii_cache.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kCommandLength = 6;  // 0x0502 control, 0x0504 address
constexpr std::uint16_t kPollLength = 14;    // 0x0502 .. 0x050F
// The header's reserved words 0x1D..0x3D (after the mailbox protocols, before the EEPROM size) are
// not read: nothing is defined there, and skipping them saves 16 of a drive's EEPROM reads.
constexpr std::size_t kHeaderReservedFrom = std::size_t{2} * (sii::kMailboxProtocols + 1U);  // byte 0x3A
constexpr std::size_t kHeaderReservedTo = std::size_t{2} * sii::kEepromSize;                 // byte 0x7C
// General category: bytes 0 (group), 2 (order) and 3 (name) are string indices.
constexpr std::size_t kGeneralIndexBytes = 4;

enum class Phase : std::uint8_t { walking, named_strings };

struct SlaveRead {
  bool active{false};     // still reading
  bool issued{false};     // a command is in flight (waiting for busy to clear)
  unsigned retries{0};
  Phase phase{Phase::walking};
  std::size_t read_at{0};  // byte offset of the next read
  std::size_t next_category{kSiiHeaderBytes};
  std::size_t strings_at{0};   // the Strings category's body, when its reading was put off (0: not)
  std::size_t strings_end{0};
  std::size_t general_at{0};   // the General category's body (0: none seen)
  hal::Nanoseconds busy_deadline{0};
};

// The end of the strings the General category names (group, order, device name), or 0 while the
// bytes read so far do not reach it yet.
std::size_t end_of_named_strings(const SiiImage& image, const SlaveRead& st) noexcept {
  const std::uint8_t* g = image.bytes.data() + st.general_at;
  const std::size_t last = std::max({g[0], g[2], g[3]});
  const std::size_t known = std::min(st.read_at, st.strings_end);
  std::size_t at = st.strings_at + 1;  // after the count byte
  for (std::size_t i = 1; i <= last; ++i) {
    if (at >= known) return 0;
    at += 1U + image.bytes[at];
  }
  return at <= known ? at : 0;
}

// Walks the categories whose headers have arrived; marks the image complete at the end marker
// or when the next category would not fit. The Strings category's body is put off (unless every
// string is wanted) and read after the end marker, only as far as the strings General names.
void walk_categories(SiiImage& image, SlaveRead& state, bool all_strings) noexcept {
  while (!image.complete && state.read_at >= state.next_category + 4) {
    const std::uint8_t* h = image.bytes.data() + state.next_category;
    const std::uint16_t type = load_le16(h);
    const std::size_t body = state.next_category + 4;
    const std::size_t next = state.next_category + 4 + std::size_t{2} * load_le16(h + 2);
    if (type == sii::kCategoryEnd) {
      image.size = static_cast<std::uint16_t>(state.next_category + 2);
      image.complete = true;
    } else if (next + 2 > kSiiImageCapacity) {
      store_le16(image.bytes.data() + state.next_category, sii::kCategoryEnd);
      image.size = static_cast<std::uint16_t>(state.next_category + 2);
      image.complete = true;
      image.truncated = true;
    } else {
      if (type == sii::kCategoryGeneral && next - body >= kGeneralIndexBytes) state.general_at = body;
      if (type == sii::kCategoryStrings && !all_strings && state.strings_at == 0 && next > body) {
        state.strings_at = body;
        state.strings_end = next;
        state.read_at = std::max(state.read_at, next);  // the body stays zero until it is read
      }
      state.next_category = next;
    }
  }
  if (!image.complete) return;
  if (state.strings_at != 0) {
    if (state.phase == Phase::walking) {  // the end marker is in: back to the strings put off
      state.phase = Phase::named_strings;
      state.read_at = state.strings_at;
    }
    // Done when General names no string, its strings are in, or the category is read to its end
    // (an index past the last string).
    const bool named_in = state.general_at == 0 || end_of_named_strings(image, state) != 0;
    if (!named_in && state.read_at < state.strings_end) return;  // read on
    image.strings_skipped = static_cast<std::uint16_t>(state.strings_end - std::min(state.read_at, state.strings_end));
  }
  state.active = false;
}

void fail(SiiImage& image, SlaveRead& state, Error error) noexcept {
  image.error = error;
  state.active = false;
}

// Once the identity is in: the cached image for exactly these first 32 bytes, if there is one.
bool take_from_cache(SiiImage& image, SlaveRead& state, const SiiCache* cache) noexcept {
  if (cache == nullptr || state.read_at != kSiiIdentityBytes) return false;
  const SiiImage* hit = cache->find(ConstByteSpan(image.bytes.data(), kSiiIdentityBytes));
  if (hit == nullptr) return false;
  image = *hit;
  image.from_cache = true;
  state.active = false;
  return true;
}

// Takes one read's data into the image at the slave's read position.
void take_data(SiiImage& image, SlaveRead& st, const std::uint8_t* data, std::size_t chunk) noexcept {
  const std::size_t room = kSiiImageCapacity - st.read_at;
  const std::size_t take = chunk < room ? chunk : room;
  std::memcpy(image.bytes.data() + st.read_at, data, take);
  st.read_at += take;
  if (st.read_at > kHeaderReservedFrom && st.read_at < kHeaderReservedTo) st.read_at = kHeaderReservedTo;
  if (st.phase == Phase::walking) image.size = static_cast<std::uint16_t>(std::max<std::size_t>(image.size, st.read_at));
}

}  // namespace

Result<SiiReadStats> read_sii_images(DatagramLink& link, Span<SiiImage> images, const SiiReadOptions& options,
                                     const SiiCache* cache) noexcept {
  SiiReadStats stats;
  const std::size_t n = images.size();
  if (n > kMaxDatagramsPerFrame / 2) return make_error(Errc::capacity_exceeded, "too many slaves for one SII frame", static_cast<std::uint32_t>(n));
  std::array<SlaveRead, kMaxDatagramsPerFrame / 2> state{};
  for (std::size_t s = 0; s < n; ++s) {
    images[s] = SiiImage{};
    state[s].active = true;
  }
  std::array<std::uint8_t, kCommandLength> command{};
  for (;;) {
    // 1. Issue a read command on every active slave without one in flight.
    FrameBuilder* frame = &link.begin();
    std::size_t added = 0;
    std::array<std::uint8_t, kMaxDatagramsPerFrame / 2> slave_of{};
    for (std::size_t s = 0; s < n; ++s) {
      if (!state[s].active || state[s].issued) continue;
      store_le16(command.data(), reg::kSiiCommandRead);
      store_le32(command.data() + 2, static_cast<std::uint32_t>(state[s].read_at / 2U));
      const auto adp = position_adp(static_cast<std::uint16_t>(s));
      if (!frame->add(Command::APWR, link.index(), make_address(adp, reg::kSiiControl), kCommandLength, ConstByteSpan(command)).ok()) {
        return make_error(Errc::capacity_exceeded, "SII command frame full");
      }
      slave_of[added++] = static_cast<std::uint8_t>(s);
    }
    if (added > 0) {
      ++stats.frames;
      const Result<FrameView> back = link.exchange(options.frame_timeout, options.attempts);
      if (!back.ok()) return back.error();
      std::size_t i = 0;
      for (const DatagramView d : back.value()) {
        SlaveRead& st = state[slave_of[i]];
        if (d.wkc() != 1) {
          fail(images[slave_of[i]], st, make_error(Errc::io_error, "SII command not taken", slave_of[i], d.wkc()));
        } else {
          st.issued = true;
          st.busy_deadline = link.clock().now() + options.busy_timeout;
        }
        ++i;
      }
    }
    // 2. Poll status and data of every slave with a command in flight.
    frame = &link.begin();
    added = 0;
    for (std::size_t s = 0; s < n; ++s) {
      if (!state[s].active || !state[s].issued) continue;
      const auto adp = position_adp(static_cast<std::uint16_t>(s));
      if (!frame->add(Command::APRD, link.index(), make_address(adp, reg::kSiiControl), kPollLength).ok()) {
        return make_error(Errc::capacity_exceeded, "SII poll frame full");
      }
      slave_of[added++] = static_cast<std::uint8_t>(s);
    }
    if (added == 0) break;  // nobody active
    ++stats.frames;
    // A busy status is judged by when the poll was sent (the state it shows), not by when the master
    // got round to reading it: a preempted master must not time out an EEPROM that finished in time.
    const hal::Nanoseconds polled_at = link.clock().now();
    const Result<FrameView> back = link.exchange(options.frame_timeout, options.attempts);
    if (!back.ok()) return back.error();
    std::size_t i = 0;
    for (const DatagramView d : back.value()) {
      const std::size_t s = slave_of[i++];
      SiiImage& image = images[s];
      SlaveRead& st = state[s];
      if (d.wkc() != 1) {
        fail(image, st, make_error(Errc::io_error, "SII status not readable", static_cast<std::uint32_t>(s), d.wkc()));
        continue;
      }
      const std::uint8_t* p = d.data().data();
      const std::uint16_t status = load_le16(p);
      if ((status & reg::kSiiBusy) != 0) {
        ++stats.busy_polls;
        if (polled_at > st.busy_deadline) {
          fail(image, st, make_error(Errc::timeout, "SII read stays busy", static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(st.read_at / 2U)));
        }
        continue;
      }
      st.issued = false;
      if ((status & reg::kSiiCommandError) != 0) {
        ++stats.command_errors;
        if (++st.retries > options.command_retries) {
          fail(image, st, make_error(Errc::io_error, "SII command error", static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(st.read_at / 2U)));
        }
        continue;  // issued again next round
      }
      st.retries = 0;
      ++stats.reads;
      take_data(image, st, p + 6, (status & reg::kSiiRead8Bytes) != 0 ? 8 : 4);
      if (take_from_cache(image, st, cache)) {
        ++stats.cache_hits;
        continue;
      }
      walk_categories(image, st, options.all_strings);
      if (st.active && st.read_at >= kSiiImageCapacity) {
        fail(image, st, make_error(Errc::capacity_exceeded, "SII image without end marker", static_cast<std::uint32_t>(s)));
      }
    }
  }
  return stats;
}

}  // namespace rescue::ecat
