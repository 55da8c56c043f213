#include "core/app/bench/bench_nic.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>

#include "core/app/bench/bench_header.hpp"
#include "core/app/config/nic_option.hpp"
#include "core/app/runtime/nic_factory.hpp"
#include "core/memory/start_up_slot.hpp"
#include "ecat/codec/frame.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {
namespace {

constexpr std::int64_t kMaxFrames = 100'000;
constexpr hal::Nanoseconds kReplyTimeout = 10 * hal::kNsPerMs;  // ten cycles: a frame later than that is lost

// Round trips, one per frame that came back (800 KB: from the heap at the bench's start, not in
// every command's image: start_up_slot.hpp).
using RoundTrips = std::array<hal::Nanoseconds, kMaxFrames>;
StartUpSlot<RoundTrips> g_round_trips_slot;

double to_us(hal::Nanoseconds ns) noexcept { return static_cast<double>(ns) / 1000.0; }

// Waits for the frame with datagram index `index`; older frames still in flight are skipped.
bool await_reply(hal::Nic& nic, std::uint8_t index, ByteSpan buffer) noexcept {
  const hal::Nanoseconds deadline = nic.clock().now() + kReplyTimeout;
  for (;;) {
    const Result<std::size_t> got = nic.receive(buffer, deadline);
    if (!got.ok()) return false;
    const auto view = ecat::FrameView::parse(ConstByteSpan(buffer.data(), got.value()));
    if (view.ok() && view.value().datagram_count() == 1 && (*view.value().begin()).index() == index) return true;
  }
}

}  // namespace

int bench_nic(const ParsedArgs& args) noexcept {
  const Result<NicChoice> choice = parse_nic_option(args.value("nic"));
  if (!choice.ok()) return fail("bench", choice.error().what);
  const Result<std::int64_t> frames = args.integer("frames", 10'000, 1, kMaxFrames);
  if (!frames.ok()) return fail("bench", "--frames must be 1..100000", frames.error());

  if (!g_round_trips_slot.reserve()) return fail("bench", "not enough memory for the round trips");
  RoundTrips& g_round_trips = g_round_trips_slot.emplace();
  SelectedNic selected;
  const Status opened = selected.open(choice.value());
  if (!opened.ok()) return fail_nic("bench", args.value("nic") != nullptr ? args.value("nic") : "sim", opened.error());
  hal::Nic& nic = *selected.nic();

  ecat::FrameBuilder builder;
  const ecat::MacAddress source{0x00, 0x52, 0x4D, 0x00, 0x00, 0x01};  // fixed, as masters use
  std::array<std::uint8_t, ecat::kMaxFrameSize> buffer{};
  hal::MonotonicClock wall;
  std::int64_t lost = 0;
  std::size_t returned = 0;
  for (std::int64_t i = 0; i < frames.value(); ++i) {
    const auto index = static_cast<std::uint8_t>(i);
    builder.reset(source);
    if (!builder.add(ecat::Command::BRD, index, 0, 2).ok()) return fail("bench", "cannot build the frame");
    const ConstByteSpan frame = builder.finish();
    const hal::Nanoseconds sent_at = wall.now();
    if (!nic.send(frame).ok() || !await_reply(nic, index, ByteSpan(buffer))) {
      ++lost;
      continue;
    }
    g_round_trips[returned++] = wall.now() - sent_at;
  }

  print_bench_header(stdout, "nic");
  (void)std::printf("nic: %s\n", nic.name());
  (void)std::printf("frame: BRD 2 bytes, 60 bytes on the wire, one in flight\n");
  (void)std::printf("frames: %lld frames\n", static_cast<long long>(frames.value()));
  (void)std::printf("lost: %lld frames\n", static_cast<long long>(lost));
  if (returned == 0) return fail("bench", "no frame came back: is a slave chain or `rescue-motion sim` on the other end?");
  std::sort(g_round_trips.begin(), g_round_trips.begin() + static_cast<std::ptrdiff_t>(returned));
  const auto at = [&](double q) { return g_round_trips[static_cast<std::size_t>(q * static_cast<double>(returned - 1))]; };
  (void)std::printf("rtt_min: %.1f us\n", to_us(at(0.0)));
  (void)std::printf("rtt_median: %.1f us\n", to_us(at(0.5)));
  (void)std::printf("rtt_p99: %.1f us\n", to_us(at(0.99)));
  (void)std::printf("rtt_max: %.1f us\n", to_us(at(1.0)));
  return 0;
}

}  // namespace rescue::app
