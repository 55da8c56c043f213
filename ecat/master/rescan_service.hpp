// ctl rescan (docs/master.md "Rescan"): the segment identified again while it cycles, and compared
// with the plan as bring-up compares it (network_match.hpp: missing, extra, wrong device, wrong
// position, revision), in the cyclic frame (never a frame of its own, never a wait), one at a time:
//   count     BRD 0x0000: its working counter is the number of devices on the wire
//   identify  per device, by auto-increment position (so a device without a station address, or
//             with another's, is read at its place): APWR 0x0502 = SII read command + word address,
//             APRD 0x0502..0x050F until the SII interface is not busy, its 2 or 4 words taken; SII
//             words 0x04..0x0F (alias, vendor, product, revision, serial), kDevicesPerFrame devices
//             a frame, round robin
//   compare   match_network(plan, devices found, the slaves held out of service and the lost ones
//             (their absence no shift of the others)), then every lost slave not found is `missing`
// It changes nothing in a slave: no AL state, SM, FMMU or process data; its only writes are the SII
// interface's read command (the register the master's own identification uses). A read the online
// recovery could collide with is avoided: refused while the recovery identifies a slave (reads its
// SII), and given up (`recovering`) if it starts to meanwhile. A device that never answers its
// reads within kMaxMisses frames, or whose SII stays busy, is `not identified`; then the comparison
// is left out (`incomplete`), the identities read are still given.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecat/master/cyclic_service.hpp"
#include "ecat/master/network_match.hpp"

namespace rescue::ecat {

constexpr std::size_t kRescanWords = 12;  // SII words 0x04..0x0F

enum class RescanStatus : std::uint8_t {
  ok = 0,          // every device identified and compared with the plan
  incomplete = 1,  // some device could not be identified: no comparison
  recovering = 2,  // the online recovery began identifying a slave: given up
};

class RescanService final : public CyclicService {
 public:
  static constexpr std::size_t kDevicesPerFrame = 4;
  static constexpr std::uint8_t kMaxMisses = 10;   // frames without an answer from a device, or of its busy SII
  static constexpr std::uint8_t kMaxCountTries = 10;

  explicit RescanService(ServiceContext& context) noexcept : ctx_(context) {}

  enum class Refusal : std::uint8_t { none, busy, recovering, not_cycling };
  // Starts a rescan; Refusal::none when taken.
  [[nodiscard]] Refusal request() noexcept;
  // A finished rescan: true once (then found(), match(), ... describe it until the next request).
  [[nodiscard]] bool take() noexcept;
  bool busy() const noexcept { return state_ != State::idle; }

  RescanStatus status() const noexcept { return status_; }
  std::uint8_t counted() const noexcept { return counted_; }  // the BRD's working counter
  Span<const FoundSlave> found() const noexcept { return {found_.data(), devices_}; }
  std::uint32_t identified() const noexcept { return identified_; }  // bit i: device i's SII read
  const NetworkMatch& match() const noexcept { return match_; }  // status ok only
  std::uint16_t frames() const noexcept { return frames_; }

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept override;
  void end_exchange(hal::Nanoseconds now) noexcept override;
  void settle(CycleResult& result) noexcept override;

 private:
  enum class State : std::uint8_t { idle, counting, identifying, done };
  static constexpr std::uint8_t kCountTag = 0xFF;
  static constexpr std::uint8_t kCommandTag = 0x40;  // tag bit: the SII read command (else its poll)
  static_assert(kMaxFoundSlaves < kCommandTag, "a device's index fits below the tag bit");
  static_assert(kMaxFoundSlaves <= 32, "identified_ holds a bit per device");

  bool any_identifying() const noexcept;
  bool device_open(std::size_t i) const noexcept { return words_read_[i] < kRescanWords && misses_[i] < kMaxMisses; }
  void finish() noexcept;

  ServiceContext& ctx_;
  State state_{State::idle};
  RescanStatus status_{RescanStatus::ok};
  std::uint8_t counted_{0};
  std::size_t devices_{0};
  bool count_answered_{false};
  std::uint8_t count_tries_{0};
  std::uint16_t frames_{0};
  std::uint32_t identified_{0};
  std::size_t rotate_{0};
  std::array<std::array<std::uint16_t, kRescanWords>, kMaxFoundSlaves> words_{};
  std::array<std::uint8_t, kMaxFoundSlaves> words_read_{};
  std::array<std::uint8_t, kMaxFoundSlaves> misses_{};
  std::array<bool, kMaxFoundSlaves> polling_{};  // the command was taken: poll its result
  std::array<FoundSlave, kMaxFoundSlaves> found_{};
  NetworkMatch match_{};
};

}  // namespace rescue::ecat
