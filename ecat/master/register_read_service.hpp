// ctl reg_read (docs/master.md "Register reads"): one read of a slave's ESC registers at a time, by
// FPRD in the cyclic frame (never a frame of its own, never a wait): the owner asks (request), the
// next frames carry the FPRD while it fits beside the other optional datagrams (it leaves the
// mailbox its room) until the slave answers (working counter 1) or kTries frames went unanswered;
// the owner takes the result (take) a period or more later. A slave out of the exchange (lost) is
// never addressed: its read ends out_of_exchange at once. Read only: there is no register write.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "ecat/master/cyclic_service.hpp"

namespace rescue::ecat {

constexpr std::uint16_t kMaxRegisterReadLength = 64;

enum class RegisterReadStatus : std::uint8_t {
  ok = 0,               // the slave answered: `data` holds `length` bytes
  not_answered = 1,     // kTries frames carried the FPRD and none came back with working counter 1
  out_of_exchange = 2,  // the slave is lost or not in the exchange: nothing was sent
};

struct RegisterReadResult {
  std::uint8_t position{0};
  std::uint16_t address{0};
  std::uint16_t length{0};
  RegisterReadStatus status{RegisterReadStatus::ok};
  std::uint16_t wkc{0};
  std::uint8_t frames{0};  // cyclic frames that carried the read
  std::array<std::uint8_t, kMaxRegisterReadLength> data{};
};

class RegisterReadService final : public CyclicService {
 public:
  static constexpr std::uint8_t kTries = 10;

  explicit RegisterReadService(ServiceContext& context) noexcept : ctx_(context) {}

  // False (nothing asked) when a read is under way or its result not yet taken, the position is
  // not planned, the length is 0 or above kMaxRegisterReadLength, or the range passes 0xFFFF.
  [[nodiscard]] bool request(std::size_t position, std::uint16_t address, std::uint16_t length) noexcept;
  // The finished read's result (once; false while none is finished).
  [[nodiscard]] bool take(RegisterReadResult& out) noexcept;
  bool busy() const noexcept { return state_ != State::idle; }

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept override;
  void end_exchange(hal::Nanoseconds now) noexcept override;

 private:
  enum class State : std::uint8_t { idle, asked, sent, done };
  ServiceContext& ctx_;
  State state_{State::idle};
  RegisterReadResult result_{};
};

}  // namespace rescue::ecat
