// hal::Nic on a real network interface: a Linux AF_PACKET raw socket bound to one named interface,
// set up the way an EtherCAT master needs it (docs/hal.md explains each setting):
//   - bound to that interface only, with a kernel (BPF) filter keeping EtherType 0x88A4, also
//     behind an 802.1Q tag, which PACKET_AUXDATA lets us put back where it was on the wire;
//   - promiscuous (PACKET_MR_PROMISC): returning frames carry whatever destination the master used;
//   - PACKET_QDISC_BYPASS: frames go straight to the driver, no queueing discipline in the way;
//   - non-blocking; how receive waits is the ReceiveWait setting: `spin` polls the socket for a
//     short while (the receive spin: a reply that comes back within it is seen at once, without the
//     wake-up of a sleeping thread) and then waits in ppoll() at most until the caller's deadline;
//     `adaptive` learns the frame's round trip and sleeps in ppoll() through most of it, spinning
//     only from a little before the expected return; `sleep` waits in ppoll() at once;
//   - our own outgoing frames ignored (PACKET_IGNORE_OUTGOING where the kernel has it, and the
//     packet type checked on every frame), other EtherTypes dropped and counted;
//   - SO_RCVBUF sized for a burst of returning frames;
//   - optionally (receive_timestamps) the kernel's software receive timestamp of each frame
//     (SO_TIMESTAMPNS), given back on the NIC's monotonic clock by last_receive_time().
// Frames are read into and sent from the caller's buffers: no heap per frame. Not thread-safe: one
// task owns the NIC (the EtherCAT handler, or the simulator's serve loop).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "hal/time/clock.hpp"
#include "hal/net/nic.hpp"

namespace rescue::hal {

using HardwareAddress = std::array<std::uint8_t, 6>;

// Linux interface names are at most 15 characters (IFNAMSIZ 16 with the terminating zero).
constexpr std::size_t kMaxInterfaceNameLength = 15;

struct RawSocketSettings {
  // Which frames the kernel hands to the socket. EtherCAT only (the BPF filter) is what a master
  // uses; every EtherType also brings all other traffic, and our own outgoing frames where the
  // kernel lacks PACKET_IGNORE_OUTGOING, to user space, where they are dropped: useful to diagnose
  // a wire, and what the tests use to prove the user-space filters.
  enum class Capture : std::uint8_t { ethercat_only, all_ethertypes };
  Capture capture{Capture::ethercat_only};
  bool promiscuous{true};
  bool qdisc_bypass{true};
  // Requested receive buffer (the kernel doubles it for bookkeeping and caps it at rmem_max unless
  // the process has CAP_NET_ADMIN). 256 KiB holds ~170 full-size frames.
  int receive_buffer_bytes{256 * 1024};
  // How long receive() keeps reading the socket without sleeping before it waits in ppoll(). A
  // frame's round trip on a segment is tens of microseconds; a thread that sleeps through it
  // is woken by the kernel on another CPU, which on an idle or virtualised CPU costs tens of
  // microseconds more (docs/hal.md has the measurements). 0: sleep at once (the simulator's side).
  Nanoseconds receive_spin{0};
  // How receive() waits for a frame (docs/hal.md, docs/timing.md has the CPU each one costs):
  //   spin      read without sleeping for up to receive_spin after the first empty read, then ppoll();
  //   adaptive  after kAdaptiveLearnFrames round trips, sleep in ppoll() until the expected return
  //             (the learnt round trip, measured from send()) minus adaptive_lead, then spin for at
  //             most receive_spin, then ppoll() until the deadline. A frame that comes back early wakes
  //             the ppoll() at once; a late one is still received and counted (wait_stats().after_spin);
  //   sleep     ppoll() at once (receive_spin ignored).
  enum class ReceiveWait : std::uint8_t { spin, adaptive, sleep };
  ReceiveWait receive_wait{ReceiveWait::spin};
  // adaptive: how long before the expected return the thread is woken to spin (covers its wake-up).
  Nanoseconds adaptive_lead{20'000};
  // Ask the kernel to timestamp each received frame (SO_TIMESTAMPNS: the instant the frame entered
  // the network stack, on veth the sender's send()). `sim --ring-iface` gives each copy of a frame
  // that time as its segment time, not the time the simulator got the CPU to read it
  // (docs/redundancy.md "DC across a break over veth"). Off for the master: it needs no stamp.
  bool receive_timestamps{false};
};

// Round trips seen before the adaptive wait trusts its estimate (spin until then).
constexpr unsigned kAdaptiveLearnFrames = 16;
// The estimate follows the round trips as an exponential mean with this weight shift (1/16 per frame).
constexpr unsigned kAdaptiveWeightShift = 4;

const char* to_string(RawSocketSettings::ReceiveWait wait) noexcept;

// Where receive() found its frames (each frame returned counts once): how the wait performs.
struct ReceiveWaitStats {
  std::uint64_t at_once{0};      // already queued at the first read
  std::uint64_t while_asleep{0};  // woke the adaptive wait's first ppoll() (came back early)
  std::uint64_t while_spinning{0};
  std::uint64_t after_spin{0};   // found after the spin, in the ppoll() up to the deadline (late)
};

// What open() obtained from the kernel, for logs and benchmark headers.
struct RawSocketFeatures {
  int interface_index{0};
  HardwareAddress hardware_address{};
  bool promiscuous{false};
  bool qdisc_bypass{false};
  bool ignore_outgoing{false};  // PACKET_IGNORE_OUTGOING (Linux 4.20+); else the packet type check
  int receive_buffer_bytes{0};  // as reported back by the kernel
  bool receive_timestamps{false};  // SO_TIMESTAMPNS accepted (asked for by the settings)
};

class RawSocketNic final : public Nic {
 public:
  RawSocketNic() = default;
  ~RawSocketNic() override;
  // Owns a file descriptor: neither copied nor moved.
  RawSocketNic(const RawSocketNic&) = delete;
  RawSocketNic& operator=(const RawSocketNic&) = delete;
  RawSocketNic(RawSocketNic&&) = delete;
  RawSocketNic& operator=(RawSocketNic&&) = delete;

  // Opens the socket on `interface_name`. Errors (detail0 = errno where the OS refused):
  //   invalid_argument  empty name or longer than 15 characters; already open
  //   not_found         no interface of that name in this network namespace
  //   permission_denied no CAP_NET_RAW (run as root, or `setcap cap_net_raw+ep rescue-motion`)
  //   refused           the interface is administratively down (`ip link set IFACE up`)
  //   io_error          any other refusal (Error::what names the call)
  Status open(const char* interface_name, const RawSocketSettings& settings = RawSocketSettings{}) noexcept;
  void close() noexcept;
  bool is_open() const noexcept { return fd_ >= 0; }
  // The socket, for a caller that waits on several interfaces in one poll() (`sim --ring-iface`);
  // -1 when closed. Reading it bypasses receive()'s filter: poll it, then call receive().
  int fd() const noexcept { return fd_; }

  // Sends one Ethernet frame as given (14..1514 bytes). busy when the driver's queue is full.
  Status send(ConstByteSpan frame) noexcept override;
  Result<std::size_t> receive(ByteSpan buffer, Nanoseconds deadline) noexcept override;
  Clock& clock() noexcept override { return clock_; }
  // "raw:IFACE", the same text as the --nic option that selects it.
  const char* name() const noexcept override { return name_.data(); }
  NicStats stats() const noexcept override { return stats_; }
  // The kernel's receive timestamp of the last frame receive() returned, converted from
  // CLOCK_REALTIME (the only clock the kernel stamps packets with) to clock() by the two clocks'
  // difference read at that receive, and never later than that read.
  Result<Nanoseconds> last_receive_time() const noexcept override;
  // Frames returned without a timestamp although one was asked for. Rare: the kernel turns stamping
  // at entry on a little after the option is set (deferred work), and stamps a frame that entered
  // before that when it is read, i.e. at the read, as without the option.
  std::uint64_t frames_without_timestamp() const noexcept { return frames_without_timestamp_; }
  const ReceiveWaitStats& wait_stats() const noexcept { return wait_stats_; }

  const RawSocketFeatures& features() const noexcept { return features_; }
  // Changes the receive spin (RawSocketSettings::receive_spin) of an open socket.
  void set_receive_spin(Nanoseconds spin) noexcept { receive_spin_ = spin < 0 ? 0 : spin; }
  Nanoseconds receive_spin() const noexcept { return receive_spin_; }
  void set_receive_wait(RawSocketSettings::ReceiveWait wait, Nanoseconds adaptive_lead) noexcept {
    receive_wait_ = wait;
    adaptive_lead_ = adaptive_lead < 0 ? 0 : adaptive_lead;
  }
  RawSocketSettings::ReceiveWait receive_wait() const noexcept { return receive_wait_; }
  // The adaptive wait's learnt round trip (send to the frame seen), 0 before kAdaptiveLearnFrames.
  Nanoseconds expected_round_trip() const noexcept {
    return learnt_frames_ >= kAdaptiveLearnFrames ? round_trip_ns_ : 0;
  }

 private:
  Status configure(const char* interface_name, const RawSocketSettings& settings) noexcept;
  // One non-blocking read. Returns the frame length, 0 when the frame was filtered out, or
  // Errc::busy when nothing is queued.
  Result<std::size_t> read_one(ByteSpan buffer) noexcept;

  MonotonicClock clock_;
  int fd_{-1};
  std::array<char, 4 + kMaxInterfaceNameLength + 1> name_{};  // "raw:" + interface name
  RawSocketFeatures features_{};
  // The first frame after a send: its round trip feeds the adaptive estimate.
  void learn_round_trip(Nanoseconds now) noexcept;
  // Sleeps in ppoll() until `until` or a frame; an error when the socket reports one (interface down).
  Status sleep_for_frame(Nanoseconds now, Nanoseconds until) noexcept;

  NicStats stats_{};
  ReceiveWaitStats wait_stats_{};
  // The last returned frame's receive timestamp on clock_, -1 when it had none.
  Nanoseconds last_receive_time_{-1};
  std::uint64_t frames_without_timestamp_{0};

  Nanoseconds receive_spin_{0};
  RawSocketSettings::ReceiveWait receive_wait_{RawSocketSettings::ReceiveWait::spin};
  Nanoseconds adaptive_lead_{20'000};
  Nanoseconds sent_at_{-1};        // the last send (adaptive only), -1 once its frame was seen
  Nanoseconds round_trip_ns_{0};   // exponential mean of the round trips
  unsigned learnt_frames_{0};
};

// True for an Ethernet frame of EtherType 0x88A4, directly or behind one 802.1Q tag.
bool is_ethercat_frame(ConstByteSpan frame) noexcept;

}  // namespace rescue::hal
