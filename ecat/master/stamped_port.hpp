// A master port (hal::Nic) that notes when it last sent a frame, the clock read just before the
// send: the closest the master comes to the instant the frame left, after the frame was built and
// whatever delayed the cycle between building and sending, and how long each send took: the host's
// part of the two copies' departures (docs/redundancy.md "DC across a break over veth").
// Everything else is passed through to the NIC underneath.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "hal/net/nic.hpp"

namespace rescue::ecat {

class StampedPort final : public hal::Nic {
 public:
  StampedPort() noexcept = default;
  explicit StampedPort(hal::Nic& inner) noexcept : inner_(&inner) {}

  void attach(hal::Nic& inner) noexcept { inner_ = &inner; }
  // Only a ring needs the stamps (the host's part of the copies' departures): without one the port
  // is a plain pass-through, so a tree master's cycle reads no extra clock.
  void stamp_sends() noexcept { stamping_ = true; }

  Status send(ConstByteSpan frame) noexcept override;
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    return inner_->receive(buffer, deadline);
  }
  hal::Clock& clock() noexcept override { return inner_->clock(); }
  const char* name() const noexcept override { return inner_->name(); }
  hal::NicStats stats() const noexcept override { return inner_->stats(); }
  Result<hal::Nanoseconds> last_receive_time() const noexcept override { return inner_->last_receive_time(); }

  // The clock just before the last frame was handed to the NIC; 0 before the first (or never, on a
  // port that does not stamp).
  hal::Nanoseconds last_sent_at() const noexcept { return last_sent_at_; }
  // How long the NIC's send took (clock after minus clock before): over a raw socket the kernel
  // stamps the frame somewhere in between, so this bounds what the stamp above cannot know.
  struct SendDurations {
    std::uint64_t sends{0};
    std::uint64_t over_5us{0};
    std::uint64_t over_20us{0};
    hal::Nanoseconds max{0};
  };
  const SendDurations& send_durations() const noexcept { return durations_; }

 private:
  hal::Nic* inner_{nullptr};
  bool stamping_{false};
  hal::Nanoseconds last_sent_at_{0};
  SendDurations durations_{};
  void count_send(hal::Nanoseconds began) noexcept;
};

}  // namespace rescue::ecat
