#include "core/app/bench/bench_codec.hpp"

#include <algorithm>
#include <array>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include "core/app/bench/bench_header.hpp"
#include "core/memory/heap_guard.hpp"
#include "core/timing/latency_histogram.hpp"
#include "core/robot/robot.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"
#include "hal/rt/rt_setup.hpp"
#include "hal/time/tsc_timer.hpp"

namespace rescue::app {
namespace {

constexpr std::int64_t kDefaultFrames = 200'000;
constexpr std::size_t kBytesPerJoint = drivers::kJointOutputBytes + drivers::kJointInputBytes;  // 28
constexpr std::uint16_t kLrwWkcPerJoint = 3;  // read + write by one slave
constexpr ecat::MacAddress kMasterMac{0x02, 0x00, 0x00, 0x00, 0x00, 0x01};
// 100 Mbit/s: 80 ns per byte; on the wire a frame also takes FCS, preamble + SFD and the gap.
constexpr std::int64_t kNsPerWireByte = 80;
constexpr std::size_t kWireOverheadBytes = 4 + 8 + 12;

struct Region {
  std::uint32_t logical_start;
  std::uint16_t joints;
  std::uint16_t length;
};

// One region per branch, in branch order, outputs then inputs of its joints.
std::array<Region, kBranchCount> regions() noexcept {
  std::array<Region, kBranchCount> r{};
  std::uint32_t offset = 0;
  for (std::size_t b = 0; b < kBranchCount; ++b) {
    const auto joints = static_cast<std::uint16_t>(
        std::count_if(kJoints.begin(), kJoints.end(), [b](const JointInfo& j) { return static_cast<std::size_t>(j.branch) == b; }));
    r[b] = Region{offset, joints, static_cast<std::uint16_t>(joints * kBytesPerJoint)};
    offset += r[b].length;
  }
  return r;
}

constexpr std::size_t kImageBytes = kJointCount * kBytesPerJoint;  // 588

// Static: touched before init complete, never faulting afterwards.
LatencyHistogram g_build_ticks;
LatencyHistogram g_decode_ticks;
LatencyHistogram g_parse_ticks;
LatencyHistogram g_timer_ticks;
std::array<std::uint8_t, kImageBytes> g_image{};
std::array<std::uint8_t, ecat::kMaxFrameSize> g_returned{};
ecat::FrameBuilder g_builder;
volatile std::uint64_t g_sink = 0;

// The cycle's frame: DC reference time, then one LRW per branch with the outputs copied in.
ConstByteSpan build_frame(const std::array<Region, kBranchCount>& r, std::uint8_t index) noexcept {
  g_builder.reset(kMasterMac);
  (void)g_builder.add(ecat::Command::FRMW, index, ecat::make_address(kStationAddressBase, ecat::reg::kDcSystemTime), 8);
  for (std::size_t b = 0; b < kBranchCount; ++b) {
    (void)g_builder.add(ecat::Command::LRW, static_cast<std::uint8_t>(index + 1 + b), r[b].logical_start, r[b].length,
                        ConstByteSpan(g_image.data() + r[b].logical_start, r[b].length));
  }
  return g_builder.finish();
}

// What the master does with the returned frame. Returns the number of branches whose working
// counter was short (0 here) plus the low bits of the DC time, so the work cannot be optimised away.
std::uint64_t decode_frame(ConstByteSpan frame, const std::array<Region, kBranchCount>& r) noexcept {
  const auto view = ecat::FrameView::parse(frame);
  if (!view.ok()) return ~std::uint64_t{0};
  std::uint64_t result = 0;
  for (const ecat::DatagramView d : view.value()) {
    if (d.command() == ecat::Command::FRMW) {
      result += load_le64(d.data().data()) & 0xFF;
      continue;
    }
    const std::size_t b = d.index_in_frame() - 1;
    if (b >= kBranchCount || d.length() != r[b].length) return ~std::uint64_t{0};
    if (d.wkc() != kLrwWkcPerJoint * r[b].joints) ++result;
    const std::size_t outputs = std::size_t{r[b].joints} * drivers::kJointOutputBytes;
    std::memcpy(g_image.data() + r[b].logical_start + outputs, d.data().data() + outputs, r[b].length - outputs);
  }
  return result;
}

// The frame as the segment returns it: DC time filled in, every LRW's working counter complete.
std::size_t prepare_returned_frame(ConstByteSpan sent, const std::array<Region, kBranchCount>& r) noexcept {
  std::memcpy(g_returned.data(), sent.data(), sent.size());
  const auto view = ecat::MutableFrameView::parse(ByteSpan(g_returned.data(), sent.size()));
  if (!view.ok()) return 0;
  for (const ecat::MutableDatagramView d : view.value()) {
    if (d.command() == ecat::Command::FRMW) {
      store_le64(d.data().data(), 0x0123456789ABCDEFULL);
      d.set_wkc(1);
    } else {
      const std::size_t b = d.index_in_frame() - 1;
      for (std::size_t i = 0; i < d.length(); ++i) d.data()[i] = static_cast<std::uint8_t>(i * 13 + b);
      d.set_wkc(static_cast<std::uint16_t>(kLrwWkcPerJoint * r[b].joints));
    }
  }
  return sent.size();
}

std::int64_t net_ns(const hal::TscTimer& timer, std::uint64_t ticks, std::uint64_t overhead_ticks) noexcept {
  return timer.to_ns(ticks > overhead_ticks ? ticks - overhead_ticks : 0);
}

}  // namespace

int bench_codec(const ParsedArgs& args) noexcept {
  const Result<std::int64_t> frames_arg = args.integer("frames", kDefaultFrames, 1000, 100'000'000);
  if (!frames_arg.ok()) return fail("bench", "--frames", frames_arg.error());
  const auto frames = static_cast<std::uint64_t>(frames_arg.value());

  // ---- init: everything that may allocate or fault ----
  print_bench_header(stdout, "codec");
  hal::RtConfig rt;
  rt.prefault_stack_bytes = std::size_t{256} * 1024;
  hal::apply_rt_config(rt).print(stdout);
  const hal::TscTimer timer = hal::TscTimer::calibrate();
  const std::array<Region, kBranchCount> r = regions();
  for (std::size_t i = 0; i < g_image.size(); ++i) g_image[i] = static_cast<std::uint8_t>(i);
  g_build_ticks.reset();
  g_decode_ticks.reset();
  g_parse_ticks.reset();
  g_timer_ticks.reset();
  const ConstByteSpan first = build_frame(r, 0);
  const std::size_t frame_bytes = first.size();
  const std::size_t datagrams = g_builder.datagram_count();
  const std::size_t returned_bytes = prepare_returned_frame(first, r);
  if (returned_bytes == 0) return fail("bench", "the cyclic frame does not parse");
  const ConstByteSpan returned(g_returned.data(), returned_bytes);
  (void)std::fflush(stdout);
  const hal::PageFaults faults_at_init = hal::page_faults_of_process();
  declare_init_complete(HeapGuardMode::count);

  // ---- measured: nothing below may allocate ----
  for (std::uint64_t i = 0; i < frames; ++i) {
    const std::uint64_t start = timer.start();
    g_timer_ticks.record(timer.stop() - start);
  }
  std::uint64_t sink = 0;
  for (std::uint64_t i = 0; i < frames; ++i) {
    const std::uint64_t start = timer.start();
    const ConstByteSpan f = build_frame(r, static_cast<std::uint8_t>(i));
    const std::uint64_t ticks = timer.stop() - start;
    sink += f.size() + f[16 + 1];  // the FRMW's index: the frame was really written
    g_build_ticks.record(ticks);
  }
  for (std::uint64_t i = 0; i < frames; ++i) {
    const std::uint64_t start = timer.start();
    const std::uint64_t result = decode_frame(returned, r);
    const std::uint64_t ticks = timer.stop() - start;
    sink += result;
    g_decode_ticks.record(ticks);
  }
  for (std::uint64_t i = 0; i < frames; ++i) {
    const std::uint64_t start = timer.start();
    const auto view = ecat::FrameView::parse(returned);
    const std::uint64_t ticks = timer.stop() - start;
    sink += view.ok() ? view.value().datagram_count() : 0;
    g_parse_ticks.record(ticks);
  }
  const HeapGuardCounters heap = heap_guard_counters();
  const hal::PageFaults faults_after = hal::page_faults_of_process();

  // ---- report ----
  const std::int64_t wire_ns = static_cast<std::int64_t>(frame_bytes + kWireOverheadBytes) * kNsPerWireByte;
  const std::uint64_t overhead = g_timer_ticks.percentile(50.0);
  const std::int64_t build_median = net_ns(timer, g_build_ticks.percentile(50.0), overhead);
  const std::int64_t build_p99 = net_ns(timer, g_build_ticks.percentile(99.0), overhead);
  const std::int64_t decode_median = net_ns(timer, g_decode_ticks.percentile(50.0), overhead);
  const std::int64_t decode_p99 = net_ns(timer, g_decode_ticks.percentile(99.0), overhead);
  const std::int64_t parse_median = net_ns(timer, g_parse_ticks.percentile(50.0), overhead);
  const auto percent_of_wire = [wire_ns](std::int64_t ns) {
    return 100.0 * static_cast<double>(ns) / static_cast<double>(wire_ns);
  };
  (void)std::printf("timer_source: %s\n", hal::to_string(timer.source()));
  (void)std::printf("frames_measured: %" PRIu64 " frames\n", frames);
  (void)std::printf("frame_datagrams: %zu datagrams\n", datagrams);
  (void)std::printf("lrw_bytes_per_joint: %zu bytes\n", kBytesPerJoint);
  (void)std::printf("frame_bytes: %zu bytes\n", frame_bytes);
  (void)std::printf("wire_time_100mbit: %" PRId64 " ns\n", wire_ns);
  (void)std::printf("timer_overhead_median: %" PRId64 " ns\n", timer.to_ns(overhead));
  (void)std::printf("build_median: %" PRId64 " ns\n", build_median);
  (void)std::printf("build_p99: %" PRId64 " ns\n", build_p99);
  (void)std::printf("decode_median: %" PRId64 " ns\n", decode_median);
  (void)std::printf("decode_p99: %" PRId64 " ns\n", decode_p99);
  (void)std::printf("parse_only_median: %" PRId64 " ns\n", parse_median);
  (void)std::printf("build_median_of_wire_time: %.3f %%\n", percent_of_wire(build_median));
  (void)std::printf("decode_median_of_wire_time: %.3f %%\n", percent_of_wire(decode_median));
  (void)std::printf("build_plus_decode_median_of_1ms_cycle: %.4f %%\n",
                    100.0 * static_cast<double>(build_median + decode_median) / 1e6);
  (void)std::printf("heap_allocations_after_init: %" PRIu64 " allocations\n", heap.allocations);
  (void)std::printf("page_faults_after_init: %" PRIu64 " faults\n",
                    (faults_after.minor - faults_at_init.minor) + (faults_after.major - faults_at_init.major));
  g_sink = sink;  // the measured work has an observable result
  return heap.allocations == 0 ? 0 : fail("bench", "heap allocation after init complete");
}

}  // namespace rescue::app
