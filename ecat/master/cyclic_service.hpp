// The master's cycle as a schedule of services (docs/master.md "Cyclic services"). Each cycle:
//   1. add_datagrams  every service, in schedule order, adds its datagrams to the frame while they
//                     fit (CycleFrame::add), each with a handle: the service and a tag of its own
//   2. the link sends the frame and waits for it
//   3. on_answer      each datagram that came back goes to the service its handle names, with its tag
//   4. end_exchange   every service: the exchange is over (also when the frame did not come back)
//   5. settle         every service, in schedule order: acts on what this cycle taught it
// A service owns its state (per slave: its part of the SlaveRecord) and decides for itself whether
// it runs in the master's current state. A new service is one class and one line in the schedule
// (Master::for_each_service). No heap: the handles of a frame live in a fixed array.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/link/datagram_link.hpp"
#include "ecat/link/network_plan.hpp"
#include "ecat/master/link_monitor.hpp"
#include "ecat/master/master_options.hpp"
#include "ecat/master/master_reports.hpp"
#include "ecat/master/slave_record.hpp"

namespace rescue::ecat {

constexpr std::uint16_t kAlStatusReadLength = 6;  // FPRD 0x0130: AL status, reserved, AL status code

// What every service may reach: the link, the plan, the image, the owner's options, the report,
// the master's state and cycle count, the slave records and the link monitor (the one loss decider).
// Owned by the Master; each field a reference to the master's own.
struct ServiceContext {
  DatagramLink& link;
  const NetworkPlan& plan;
  const ProcessImageLayout& layout;
  ByteSpan image;
  const MasterOptions& options;
  BringUpReport& report;
  MasterState& state;
  const std::uint64_t& cycle;
  SlaveRecords& slaves;
  LinkMonitor& monitor;
  const SlaveMask& dc_slaves;                // slaves with distributed clocks (bring-up)
  const std::uint16_t& reference_station;    // the DC reference clock's station address

  SlaveMask operated() const noexcept { return report.match.operated; }
  SlaveMask present() const noexcept { return report.match.present; }
  hal::Nanoseconds now() const noexcept { return link.clock().now(); }
  // The DC reference clock's position (kMaxSlaves before the distributed clocks are set up).
  std::size_t reference_position() const noexcept {
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if ((dc_slaves & slave_bit(p)) != 0 && plan[p].station_address == reference_station) return p;
    }
    return kMaxSlaves;
  }
  // The reference clock is out of the exchange (lost, restarted, being recovered): its time is not the network's.
  bool reference_out() const noexcept {
    const std::size_t p = reference_position();
    return p < kMaxSlaves && (monitor.out_of_exchange() & slave_bit(p)) != 0;
  }
};

class CycleFrame;

class CyclicService {
 public:
  CyclicService() = default;
  CyclicService(const CyclicService&) = delete;
  CyclicService& operator=(const CyclicService&) = delete;
  CyclicService(CyclicService&&) = delete;
  CyclicService& operator=(CyclicService&&) = delete;
  // Virtual although no service is ever destroyed through this interface (each is a Master member).
  virtual ~CyclicService() = default;

  virtual void add_datagrams(CycleFrame& frame) noexcept = 0;
  // A datagram this service added came back: `tag` as given to CycleFrame::add.
  virtual void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept = 0;
  virtual void end_exchange(hal::Nanoseconds /*now*/) noexcept {}
  virtual void settle(CycleResult& /*result*/) noexcept {}
};

// The frame under way and, per datagram, the handle of the service that handles its answer.
class CycleFrame {
 public:
  // Room kept for the mailbox's step by every optional datagram (probes, recovery, diagnostics).
  static constexpr std::size_t kMailboxReserve = 2 * kDatagramOverhead + 1 + 256;

  // Starts a cycle's frame: `builder` just begun by the link, its datagrams indexed `index`.
  void begin(FrameBuilder& builder, std::uint8_t index) noexcept {
    builder_ = &builder;
    index_ = index;
    count_ = 0;
  }

  // Adds a datagram answered to `by` with `tag`; false (frame unchanged) when it does not fit.
  bool add(CyclicService& by, std::uint8_t tag, Command command, std::uint32_t address, std::uint16_t length,
           ConstByteSpan data = {}) noexcept {
    if (!builder_->add(command, index_, address, length, data).ok()) return false;
    note(by, tag);
    return true;
  }
  // For a service that adds through the builder itself (the mailbox client): its next datagram's handle.
  void note(CyclicService& by, std::uint8_t tag) noexcept {
    if (count_ < handles_.size()) handles_[count_++] = Handle{&by, tag};
  }
  // Whether an optional datagram of `bytes` data fits and still leaves the mailbox its room.
  bool fits(std::size_t bytes) const noexcept { return builder_->remaining_data_capacity() >= bytes + kMailboxReserve; }
  std::size_t remaining() const noexcept { return builder_->remaining_data_capacity(); }
  FrameBuilder& builder() noexcept { return *builder_; }
  std::uint8_t index() const noexcept { return index_; }
  std::size_t datagrams() const noexcept { return count_; }

  // Hands each datagram of the returned frame to the service that added it, in frame order.
  void dispatch(const FrameView& back) const noexcept {
    std::size_t i = 0;
    for (const DatagramView d : back) {
      if (i >= count_) break;
      const Handle& h = handles_[i++];
      h.service->on_answer(h.tag, d);
    }
  }

 private:
  struct Handle {
    CyclicService* service;
    std::uint8_t tag;
  };
  FrameBuilder* builder_{nullptr};
  std::uint8_t index_{0};
  std::array<Handle, kMaxDatagramsPerFrame> handles_{};
  std::size_t count_{0};
};

}  // namespace rescue::ecat
