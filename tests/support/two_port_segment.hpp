// A two-port fake segment for the redundant master's tests: n slaves in a line whose first slave is
// cabled to the master's main port and whose last slave to its ring port, each port a hal::Nic on
// one virtual clock. Cable c joins slave c-1 and slave c (cable 0: main port to slave 0, cable n:
// slave n-1 to the ring port); any set of them can be cut. As an ESC forwards (the processing unit
// after port 0; a port without a link closes its loop):
//   sent on main: processed by slaves [0, first cut), back on main; no cut: by all, back on ring;
//   sent on ring: passes unprocessed down to the slave behind the last cut, which loops it: processed
//                 by [last cut, n), back on ring; no cut: by none, back on main;
//   a cut at the port it was sent on: lost;
//   damaged (damage_next): processed as above, then lost (its FCS broken on the way back).
// Each slave (station address kStation0 + i) answers: BRD/BWR with working counter +1; FPRD/FPWR of
// its station with +1 (an FPRD reads fprd_byte(i) into every byte, of the AL status 0x0130: OP); LRW
// over one branch's image (outputs first) with +3, its input byte (logical n + i) set to
// input_byte(i), its output byte (logical i) taken; APRD/APWR at
// position 0 with +1 (counted: position_hits); FRMW +1 (counted: frmw_hits). NOP: nothing.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "core/base/endian.hpp"
#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/codec/frame.hpp"
#include "hal/net/nic.hpp"
#include "hal/time/clock.hpp"

namespace rescue::test {

class TwoPortSegment {
 public:
  static constexpr std::size_t kMaxSlaves = 16;
  static constexpr std::uint16_t kStation0 = 0x1000;
  static constexpr std::uint16_t kAlStatusRegister = 0x0130;
  static constexpr std::uint16_t kAlStateOp = 0x0008;
  static constexpr hal::Nanoseconds kRoundTrip = 10 * hal::kNsPerUs;
  static constexpr std::uint8_t input_byte(std::size_t i) noexcept { return static_cast<std::uint8_t>(0x80U | i); }
  static constexpr std::uint8_t fprd_byte(std::size_t i) noexcept { return static_cast<std::uint8_t>(0x40U | i); }

  class Port final : public hal::Nic {
   public:
    Port(TwoPortSegment& segment, bool ring) noexcept : segment_(segment), ring_(ring) {}
    Status send(ConstByteSpan frame) noexcept override {
      ++stats_.frames_sent;
      segment_.carry(frame, ring_);
      return Status::success();
    }
    Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
      hal::VirtualClock& clock = segment_.clock_;
      if (count_ > 0 && queue_[head_].ready_at <= (deadline > clock.now() ? deadline : clock.now())) {
        const Pending& p = queue_[head_];
        clock.sleep_until(p.ready_at);
        std::memcpy(buffer.data(), p.bytes.data(), p.length);
        head_ = (head_ + 1) % queue_.size();
        --count_;
        ++stats_.frames_received;
        return p.length;
      }
      clock.sleep_until(deadline);
      ++stats_.receive_timeouts;
      return make_error(Errc::timeout, "nothing");
    }
    hal::Clock& clock() noexcept override { return segment_.clock_; }
    const char* name() const noexcept override { return ring_ ? "fake-ring" : "fake-main"; }
    hal::NicStats stats() const noexcept override { return stats_; }

    void deliver(const std::uint8_t* bytes, std::size_t length, hal::Nanoseconds at) noexcept {
      if (count_ == queue_.size()) return;
      Pending& p = queue_[(head_ + count_) % queue_.size()];
      std::memcpy(p.bytes.data(), bytes, length);
      p.length = length;
      p.ready_at = at;
      ++count_;
    }

   private:
    struct Pending {
      std::array<std::uint8_t, ecat::kMaxFrameSize> bytes{};
      std::size_t length{0};
      hal::Nanoseconds ready_at{0};
    };
    TwoPortSegment& segment_;
    bool ring_;
    std::array<Pending, 8> queue_{};
    std::size_t head_{0};
    std::size_t count_{0};
    hal::NicStats stats_{};
  };

  explicit TwoPortSegment(std::size_t slaves) noexcept : n_(slaves < kMaxSlaves ? slaves : kMaxSlaves) {}

  hal::Nic& main() noexcept { return main_; }
  hal::Nic& ring() noexcept { return ring_; }
  hal::VirtualClock& clock() noexcept { return clock_; }
  std::size_t slaves() const noexcept { return n_; }

  void cut(std::size_t cable) noexcept { cut_[cable] = true; }
  void restore(std::size_t cable) noexcept { cut_[cable] = false; }
  void restore_all() noexcept { cut_ = {}; }
  // The next frame sent on the ring port (`ring`) or the main port is processed, then lost.
  void damage_next(bool ring) noexcept { (ring ? damage_ring_ : damage_main_) = true; }
  std::uint8_t output_of(std::size_t slave) const noexcept { return outputs_[slave]; }
  unsigned position_hits(std::size_t slave) const noexcept { return position_hits_[slave]; }
  unsigned frmw_hits(std::size_t slave) const noexcept { return frmw_hits_[slave]; }

 private:
  void carry(ConstByteSpan frame, bool sent_on_ring) noexcept {
    std::array<std::uint8_t, ecat::kMaxFrameSize> bytes{};
    if (frame.size() > bytes.size()) return;
    std::memcpy(bytes.data(), frame.data(), frame.size());
    const auto parsed = ecat::BasicFrameView<std::uint8_t>::parse(ByteSpan(bytes.data(), frame.size()));
    if (!parsed.ok()) return;
    std::size_t first = 0;  // processed by slaves [first, end)
    std::size_t end = 0;
    bool back_on_ring = false;
    if (!sent_on_ring) {
      if (cut_[0]) return;
      std::size_t c = 1;
      while (c <= n_ && !cut_[c]) ++c;
      end = c <= n_ ? c : n_;
      back_on_ring = c > n_;  // no cut: through every slave and out at the ring port
    } else {
      if (cut_[n_]) return;
      std::size_t c = n_;
      while (c > 0 && !cut_[c - 1]) --c;
      const bool looped = c > 0;  // the slave behind the last cut (cable c - 1) closed its port 0
      first = looped ? c - 1 : n_;
      end = n_;
      back_on_ring = looped;
    }
    for (std::size_t i = first; i < end; ++i) process(parsed.value(), i);
    bool& damaged = sent_on_ring ? damage_ring_ : damage_main_;
    if (damaged) {
      damaged = false;
      return;
    }
    Port& out = back_on_ring ? ring_ : main_;
    out.deliver(bytes.data(), frame.size(), clock_.now() + kRoundTrip);
  }

  void process(const ecat::BasicFrameView<std::uint8_t>& frame, std::size_t i) noexcept {
    using ecat::Command;
    for (const ecat::MutableDatagramView d : frame) {
      std::uint8_t* data = d.data().data();
      const std::size_t length = d.length();
      switch (d.command()) {
        case Command::BRD: case Command::BWR: case Command::BRW:
          d.set_adp(static_cast<std::uint16_t>(d.adp() + 1));
          d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 1));
          break;
        case Command::FPRD: case Command::FPWR:
          if (d.adp() != kStation0 + i) break;
          if (d.command() == Command::FPRD) {
            std::memset(data, fprd_byte(i), length);
            if (d.ado() == kAlStatusRegister && length >= 6) {  // AL status: OP, code 0
              store_le16(data, kAlStateOp);
              store_le16(data + 2, 0);
              store_le16(data + 4, 0);
            }
          }
          d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 1));
          break;
        case Command::LRW: {
          // One branch of n slaves with a byte each way: outputs at logical i, inputs at n + i.
          const std::uint32_t logical = d.address();
          const std::size_t out_at = i;
          const std::size_t in_at = n_ + i;
          if (out_at < logical || in_at >= logical + length) break;
          outputs_[i] = data[out_at - logical];
          data[in_at - logical] = input_byte(i);
          d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 3));
          break;
        }
        case Command::APRD: case Command::APWR:
          if (d.adp() == 0) {
            ++position_hits_[i];
            d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 1));
          }
          d.set_adp(static_cast<std::uint16_t>(d.adp() + 1));
          break;
        case Command::FRMW:
          ++frmw_hits_[i];
          d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 1));
          break;
        default:
          break;
      }
    }
  }

  std::size_t n_;
  hal::VirtualClock clock_{hal::kNsPerSec};
  Port main_{*this, false};
  Port ring_{*this, true};
  std::array<bool, kMaxSlaves + 1> cut_{};
  bool damage_main_{false};
  bool damage_ring_{false};
  std::array<std::uint8_t, kMaxSlaves> outputs_{};
  std::array<unsigned, kMaxSlaves> position_hits_{};
  std::array<unsigned, kMaxSlaves> frmw_hits_{};
};

}  // namespace rescue::test
