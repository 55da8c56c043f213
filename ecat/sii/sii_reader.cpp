#include "ecat/sii/sii_reader.hpp"

#include <cstring>

#include "ecat/codec/registers.hpp"
#include "ecat/sii/sii_cache.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kCommandLength = 6;  // 0x0502 control, 0x0504 address
constexpr std::uint16_t kPollLength = 14;    // 0x0502 .. 0x050F
constexpr std::uint16_t kCategoryEnd = 0xFFFF;

struct SlaveRead {
  bool active{false};     // still reading
  bool issued{false};     // a command is in flight (waiting for busy to clear)
  unsigned retries{0};
  std::size_t next_category{kSiiHeaderBytes};
  hal::Nanoseconds busy_deadline{0};
};

// Walks the categories whose headers have arrived; marks the image complete at the end marker
// or when the next category would not fit.
void walk_categories(SiiImage& image, SlaveRead& state) noexcept {
  while (!image.complete && image.size >= state.next_category + 4) {
    const std::uint8_t* h = image.bytes.data() + state.next_category;
    const std::uint16_t type = load_le16(h);
    const std::size_t next = state.next_category + 4 + std::size_t{2} * load_le16(h + 2);
    if (type == kCategoryEnd) {
      image.size = static_cast<std::uint16_t>(state.next_category + 2);
      image.complete = true;
    } else if (next + 2 > kSiiImageCapacity) {
      store_le16(image.bytes.data() + state.next_category, kCategoryEnd);
      image.size = static_cast<std::uint16_t>(state.next_category + 2);
      image.complete = true;
      image.truncated = true;
    } else {
      state.next_category = next;
    }
  }
  if (image.complete) state.active = false;
}

void fail(SiiImage& image, SlaveRead& state, Error error) noexcept {
  image.error = error;
  state.active = false;
}

// Once the identity is in: the cached image for exactly these first 32 bytes, if there is one.
bool take_from_cache(SiiImage& image, SlaveRead& state, const SiiCache* cache) noexcept {
  if (cache == nullptr || image.size != kSiiIdentityBytes) return false;
  const SiiImage* hit = cache->find(image.view());
  if (hit == nullptr) return false;
  std::memcpy(image.bytes.data(), hit->bytes.data(), hit->size);
  image.size = hit->size;
  image.complete = true;
  image.from_cache = true;
  state.active = false;
  return true;
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
      store_le32(command.data() + 2, images[s].size / 2U);
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
          fail(image, st, make_error(Errc::timeout, "SII read stays busy", static_cast<std::uint32_t>(s), image.size / 2U));
        }
        continue;
      }
      st.issued = false;
      if ((status & reg::kSiiCommandError) != 0) {
        ++stats.command_errors;
        if (++st.retries > options.command_retries) {
          fail(image, st, make_error(Errc::io_error, "SII command error", static_cast<std::uint32_t>(s), image.size / 2U));
        }
        continue;  // issued again next round
      }
      st.retries = 0;
      const std::size_t chunk = (status & reg::kSiiRead8Bytes) != 0 ? 8 : 4;
      const std::size_t room = kSiiImageCapacity - image.size;
      const std::size_t take = chunk < room ? chunk : room;
      std::memcpy(image.bytes.data() + image.size, p + 6, take);
      image.size = static_cast<std::uint16_t>(image.size + take);
      if (take_from_cache(image, st, cache)) {
        ++stats.cache_hits;
        continue;
      }
      walk_categories(image, st);
      if (st.active && image.size >= kSiiImageCapacity) {
        fail(image, st, make_error(Errc::capacity_exceeded, "SII image without end marker", static_cast<std::uint32_t>(s)));
      }
    }
  }
  return stats;
}

}  // namespace rescue::ecat
