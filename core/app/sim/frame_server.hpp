// Serves an EtherCAT segment on a NIC, as a real slave chain does on the wire: each frame the
// master sends is received, processed by the segment, and sent back on the same interface with
// the source MAC marked the way every ESC marks it. Used by `rescue-motion sim --iface IFACE`.
//
//   master --frame--> NIC --receive--> FrameProcessor (the simulated segment) --send--> master
//
// No heap: one frame buffer inside the server; the processor works on it in place.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/codec/frame.hpp"
#include "hal/time/clock.hpp"
#include "hal/net/nic.hpp"

namespace rescue::app {

// What the slave chain does to a frame: the simulated segment, or a stand-in in tests.
class FrameProcessor {
 public:
  FrameProcessor() = default;
  FrameProcessor(const FrameProcessor&) = delete;
  FrameProcessor& operator=(const FrameProcessor&) = delete;
  FrameProcessor(FrameProcessor&&) = delete;
  FrameProcessor& operator=(FrameProcessor&&) = delete;
  virtual ~FrameProcessor() = default;

  virtual std::size_t slave_count() const noexcept = 0;
  // Processes the frame in `frame` in place; `arrival` is when it arrived (the NIC's clock). Returns
  // the length of the frame that goes back to the master, or an error when none goes back (a frame
  // the segment cannot parse, or one it lost on purpose).
  virtual Result<std::size_t> process(ByteSpan frame, hal::Nanoseconds arrival) noexcept = 0;
  // No frame came until `now`: bring the slaves' own time up to it (hardware runs while the wire is
  // quiet), so the next frame finds only the last moments left to simulate, however long the
  // segment was idle.
  virtual void idle(hal::Nanoseconds now) noexcept { (void)now; }
};

struct FrameServerCounters {
  std::uint64_t frames_received{0};
  std::uint64_t frames_timestamped{0};  // served at the NIC's receive timestamp, not at the read
  std::uint64_t frames_returned{0};
  std::uint64_t frames_not_returned{0};  // the processor kept them (malformed or lost on purpose)
  std::uint64_t send_errors{0};
  std::uint64_t idle_steps{0};  // quiet waits after which the segment caught up with the time
  std::uint64_t frames_held{0};  // replies held back by a stall, sent together when it ended
  std::uint64_t frames_held_dropped{0};  // a stall held more than kHeldCapacity: the rest were lost
};

// What every ESC does to a frame passing its EtherCAT processing unit: it sets SOURCE_MAC[1], the
// locally-administered bit (0x02 of the first source-address byte), so the master can tell the
// frames it sent from the ones coming back. Setting it is idempotent: after the first slave every
// further one changes nothing. Frames shorter than an Ethernet header are left alone.
void mark_processed_by_esc(ByteSpan frame) noexcept;

class FrameServer {
 public:
  // A VLAN-tagged frame of full size still fits.
  static constexpr std::size_t kBufferSize = ecat::kMaxFrameSize + ecat::kVlanTagSize;

  FrameServer(hal::Nic& nic, FrameProcessor& processor) noexcept : nic_(nic), processor_(processor) {}

  // Waits until `deadline` (on the NIC's clock) for one frame and serves it, as arrived at the NIC's
  // receive timestamp when the NIC has one (hal::Nic::last_receive_time), else at the clock read
  // after the receive: on a wire the frame reaches the slaves when it is sent, however late the
  // host lets the simulator read it (two copies of a ring frame, read one after the other, then
  // pass the segment at the instants they were sent). Errc::timeout when no
  // frame came (the processor's idle() has then caught up with the deadline); other NIC errors
  // are returned as they are. A frame the processor keeps, or one the
  // NIC cannot send, is counted, not an error: the master sees a lost frame, as on a real wire.
  Status serve_one(hal::Nanoseconds deadline) noexcept;

  const FrameServerCounters& counters() const noexcept { return counters_; }
  // The segment time the last frame was served at, and how long after it the server read it.
  hal::Nanoseconds last_arrival() const noexcept { return last_arrival_; }
  hal::Nanoseconds last_read_delay() const noexcept { return last_read_delay_; }

  // A stall of the host or of an interrupt-coalescing NIC, injected: until `until` (NIC clock)
  // replies are processed at once but held back, then sent together, in order, bunched (what a
  // capture of issue 11 showed). At most kHeldCapacity are held; the rest are lost and counted.
  static constexpr std::size_t kHeldCapacity = 16;
  void stall_until(hal::Nanoseconds until) noexcept { stall_until_ = until; }

 private:
  void release_held() noexcept;
  // The segment time of the frame just received: its receive timestamp, never later than now.
  hal::Nanoseconds arrival_of_last_frame() noexcept;

  hal::Nic& nic_;
  FrameProcessor& processor_;
  FrameServerCounters counters_{};
  std::array<std::uint8_t, kBufferSize> buffer_{};
  hal::Nanoseconds stall_until_{0};
  hal::Nanoseconds last_arrival_{0};
  hal::Nanoseconds last_read_delay_{0};
  std::array<std::array<std::uint8_t, kBufferSize>, kHeldCapacity> held_{};
  std::array<std::size_t, kHeldCapacity> held_length_{};
  std::size_t held_count_{0};
};

}  // namespace rescue::app
