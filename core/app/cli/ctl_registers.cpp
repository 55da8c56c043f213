#include "core/app/cli/ctl_registers.hpp"

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>

#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "core/robot/robot.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;
using protocol::RegStatus;

char g_text[200];  // a usage error's text (ctl is one verb per process)

// A number 0..max written in decimal or as 0x hex, the whole argument; false otherwise.
bool parse_number(const char* text, unsigned long max, unsigned long& out) noexcept {
  if (text == nullptr || *text == '\0' || *text == '-' || *text == '+') return false;
  char* end = nullptr;
  errno = 0;
  const unsigned long v = std::strtoul(text, &end, 0);
  if (errno != 0 || end == text || *end != '\0' || v > max) return false;
  out = v;
  return true;
}

const char* reason_of(RegStatus s) noexcept {
  switch (s) {
    case RegStatus::ok: return "";
    case RegStatus::lost: return "the slave is lost or out of the exchange: nothing was sent";
    case RegStatus::not_answered: return "the slave did not answer the FPRD in 10 cyclic frames";
    case RegStatus::busy: return "another register read is under way; try again";
    case RegStatus::no_answer: return "the EtherCAT handler did not answer within 0.5 s";
  }
  return "?";
}

}  // namespace

Result<Message> build_reg_read(const ParsedArgs& args, CtlPeer& /*peer*/) noexcept {
  const std::size_t position = planned_slave_named(args.positional(1));
  if (position >= kSlaveCount) {
    (void)std::snprintf(g_text, sizeof g_text, "reg_read SLAVE: '%.40s' is not a slave; a slave's name (ctl slaves) or a position 0..%zu",
                        args.positional(1), kSlaveCount - 1);
    return make_error(Errc::invalid_argument, g_text);
  }
  unsigned long address = 0;
  if (!parse_number(args.positional(2), 0xFFFF, address)) {
    (void)std::snprintf(g_text, sizeof g_text, "reg_read ADDR: '%.20s' is not a register address 0x0000..0xFFFF", args.positional(2));
    return make_error(Errc::invalid_argument, g_text);
  }
  unsigned long length = 1;
  const char* len = args.positional_count() > 3 ? args.positional(3) : nullptr;
  if (len != nullptr && (!parse_number(len, protocol::kRegDataSize, length) || length == 0)) {
    (void)std::snprintf(g_text, sizeof g_text, "reg_read LEN: '%.20s' is not a length 1..%zu", len, protocol::kRegDataSize);
    return make_error(Errc::invalid_argument, g_text);
  }
  if (address + length > 0x10000UL) {
    (void)std::snprintf(g_text, sizeof g_text, "reg_read: 0x%04lX + %lu bytes passes 0xFFFF", address, length);
    return make_error(Errc::invalid_argument, g_text);
  }
  Message m;
  m.header.type = MessageType::reg_read;
  m.reg_read.slave = static_cast<std::uint8_t>(position);
  m.reg_read.address = static_cast<std::uint16_t>(address);
  m.reg_read.length = static_cast<std::uint16_t>(length);
  return m;
}

int print_reg_result(const Message& request, const Message& answer) noexcept {
  if (answer.header.type != MessageType::reg_result) return ctl_unexpected_answer(answer);
  const protocol::RegResultPayload& r = answer.reg_result;
  if (r.slave != request.reg_read.slave || r.address != request.reg_read.address || r.length != request.reg_read.length) {
    return ctl_error(CtlExit::bad_answer, "reg_read: an answer for another read");
  }
  const bool ok = r.status == RegStatus::ok;
  const char* name = planned_slave_name(r.slave);
  if (ctl_output().json) {
    begin_json(ok);
    (void)std::printf(R"(,"slave":"%s","position":%u,"address":"0x%04X","length":%u,"status":"%s")", name,
                      static_cast<unsigned>(r.slave), static_cast<unsigned>(r.address), static_cast<unsigned>(r.length),
                      protocol::to_string(r.status));
    if (ok) {
      (void)std::printf(R"(,"wkc":%u,"frames":%u,"bytes":")", static_cast<unsigned>(r.wkc), static_cast<unsigned>(r.frames));
      for (std::size_t i = 0; i < r.length; ++i) (void)std::printf("%02x", r.data[i]);
      (void)std::printf("\"");
    } else {
      (void)std::printf(R"(,"reason":)");
      print_json_string(reason_of(r.status));
    }
    end_json();
    return ok ? 0 : static_cast<int>(CtlExit::refused);
  }
  if (!ok) {
    (void)std::printf("reg_read: %s 0x%04X: %s: %s\n", name, static_cast<unsigned>(r.address), protocol::to_string(r.status),
                      reason_of(r.status));
    return static_cast<int>(CtlExit::refused);
  }
  // 16 bytes a line, each line led by the address of its first byte (as `ethercat reg_read`'s hex).
  for (std::size_t at = 0; at < r.length; at += 16) {
    (void)std::printf("0x%04zX:", r.address + at);
    for (std::size_t i = at; i < r.length && i < at + 16; ++i) (void)std::printf(" %02x", r.data[i]);
    (void)std::printf("\n");
  }
  return 0;
}

}  // namespace rescue::app
