// ctl reg_read SLAVE ADDR [LEN] (docs/operator.md "ESC registers", docs/protocol.md "Register
// reads"): a read-only read of a slave's ESC registers, as it travels on the wire (RegReadPayload,
// RegResultPayload) and between the socket handler and the EtherCAT handler (RegReadLinkRequest,
// RegReadLinkResult: one bounded queue each way in TaskLinks, reg_requests / reg_results). The
// EtherCAT handler hands it to its master, which sends one FPRD in the cyclic frame
// (ecat/master/register_read_service.hpp). There is no register write.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace rescue::app::protocol {

constexpr std::size_t kRegDataSize = 64;  // the longest read (ecat::kMaxRegisterReadLength)

// reg_read: the slave's position, the first register's address, how many bytes (1..kRegDataSize;
// address + length <= 0x10000).
struct RegReadPayload {
  std::uint8_t slave{0};
  std::uint16_t address{0};
  std::uint16_t length{0};
};

// How a register read ended (reg_result's status).
enum class RegStatus : std::uint8_t {
  ok = 0,
  lost = 1,        // refused: the slave is lost or out of the exchange; nothing was sent
  not_answered = 2,  // the FPRD went out in several frames and the slave never answered it
  busy = 3,        // another read is under way: nothing was sent; try again
  no_answer = 4,   // the EtherCAT handler did not answer in time (the socket handler's own limit)
};
constexpr std::uint8_t kRegStatusLast = 4;

constexpr const char* to_string(RegStatus s) noexcept {
  switch (s) {
    case RegStatus::ok: return "ok";
    case RegStatus::lost: return "lost";
    case RegStatus::not_answered: return "not answered";
    case RegStatus::busy: return "busy";
    case RegStatus::no_answer: return "no answer";
  }
  return "?";
}

// reg_result: the request echoed, the status, the working counter and how many frames carried the
// read, and `length` bytes of data when ok (the rest zero).
struct RegResultPayload {
  std::uint64_t request_sequence{0};
  std::uint8_t slave{0};
  RegStatus status{RegStatus::ok};
  std::uint16_t address{0};
  std::uint16_t length{0};
  std::uint16_t wkc{0};
  std::uint8_t frames{0};
  std::array<std::uint8_t, kRegDataSize> data{};
};

}  // namespace rescue::app::protocol

namespace rescue::app {

// socket handler -> EtherCAT handler (TaskLinks::reg_requests).
struct RegReadLinkRequest {
  std::uint32_t id{0};  // the socket handler's, echoed in the result
  protocol::RegReadPayload read{};
};

// EtherCAT handler -> socket handler (TaskLinks::reg_results); request_sequence is the socket handler's.
struct RegReadLinkResult {
  std::uint32_t id{0};
  protocol::RegResultPayload result{};
};

}  // namespace rescue::app
