#include "core/app/bench/wcet_operator_load.hpp"

#include <array>

#include "core/app/tasks/period_mark.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"

namespace rescue::app {
namespace {

constexpr std::int64_t kStartUnixNs = 1'800'000'000'000'000'000LL;  // the bench's own wall clock
constexpr std::int64_t kPeriodNs = 1'000'000;                        // one wake-up per 1 ms period
constexpr std::uint64_t kEpoch = 0x5EED5EED5EED5EEDULL;
constexpr std::uint32_t kOperator = 3;                // the operator's sender id
constexpr std::size_t kSdoLabelBytes = 160;           // the label's whole capacity: longer than one mailbox, so segmented
constexpr std::uint16_t kLabelIndex = 0x2010;         // the drive's label (a visible string of up to 256 bytes)
// The heavy verbs in turn; every eighth datagram of a flood is the SDO transfer's (busy while one is in flight).
constexpr protocol::MessageType kHeavyVerbs[] = {
    protocol::MessageType::get_status, protocol::MessageType::get_slaves, protocol::MessageType::get_slave_info,
    protocol::MessageType::get_graph,  protocol::MessageType::get_sii,    protocol::MessageType::get_tasks,
    protocol::MessageType::get_diag,   protocol::MessageType::sdo_upload,
};
constexpr std::size_t kVerbCount = sizeof kHeavyVerbs / sizeof kHeavyVerbs[0];

std::array<hal::UdpDatagram, 16> g_answers;  // the client's receive buffers (static: no heap, not on the stack)

}  // namespace

WcetOperatorLoad::WcetOperatorLoad(const SocketHandlerPorts& ports) noexcept
    : wall_(kStartUnixNs), handler_(ports, key_, window_, wall_) {
  window_.begin_epoch(kEpoch);
}

Status WcetOperatorLoad::open() noexcept {
  SocketHandlerOptions options;
  options.listen = "127.0.0.1";
  options.control_port = 0;
  options.sensor_port = 0;
  const Status ports = handler_.open(options);
  if (!ports.ok()) return ports;
  const Status client = client_.open("127.0.0.1", 0);
  if (!client.ok()) return client;
  const Result<std::uint32_t> loopback = hal::parse_ipv4("127.0.0.1");
  if (!loopback.ok()) return loopback.error();
  loopback_ = loopback.value();
  return {};
}

protocol::Message WcetOperatorLoad::next_heavy() noexcept {
  protocol::Message m;
  m.header.type = kHeavyVerbs[verb_ % kVerbCount];
  if (m.header.type == protocol::MessageType::get_sii) {
    // sii_read's chunks: every slave, the image's chunks in turn.
    const std::uint64_t n = verb_ / kVerbCount;
    m.sii_request.slave = static_cast<std::uint8_t>(n % protocol::kMaxSlaves);
    m.sii_request.offset = static_cast<std::uint16_t>(((n / protocol::kMaxSlaves) % (protocol::kSiiImageBytes / protocol::kSiiChunkBytes)) *
                                                      protocol::kSiiChunkBytes);
  } else if (m.header.type == protocol::MessageType::sdo_upload && sdo_in_flight_) {
    m.header.type = protocol::MessageType::get_status;  // one transfer at a time: the next verb instead of a `busy`
  } else if (m.header.type == protocol::MessageType::sdo_upload) {
    // A 200-byte download to a drive's label, then its upload, on the next joint each time.
    ++sdo_;
    const bool download = (sdo_ % 2) == 1;
    m.header.type = download ? protocol::MessageType::sdo_download : protocol::MessageType::sdo_upload;
    m.sdo.joint = static_cast<std::uint8_t>((sdo_ / 2) % kJointCount);
    m.sdo.index = kLabelIndex;
    m.sdo.size = download ? static_cast<std::uint16_t>(kSdoLabelBytes) : 0;
    for (std::size_t i = 0; download && i < kSdoLabelBytes; ++i) m.sdo.data[i] = static_cast<std::uint8_t>('a' + i % 26);
    sdo_in_flight_ = true;
  }
  ++verb_;
  return m;
}

void WcetOperatorLoad::send(protocol::Message m) noexcept {
  m.header.version = protocol::kVersion;
  m.header.sender = kOperator;
  m.header.robot = handler_.robot_id();
  m.header.epoch = window_.epoch();
  // Strictly increasing per sender, within the robot's clock: its wall time plus the datagram's place.
  m.header.sequence = static_cast<std::uint64_t>(wall_.unix_time_ns()) + in_period_++;
  std::array<std::uint8_t, protocol::kMaxDatagram> out{};
  const Result<std::size_t> size = protocol::seal(m, key_, ByteSpan(out));
  const bool sent = size.ok() && client_.send_to(loopback_, handler_.control_port(), ConstByteSpan(out.data(), size.value())).ok();
  send_failures_ += sent ? 0U : 1U;
  ++sent_;
}

void WcetOperatorLoad::before(bool flood) noexcept {
  wall_.set(wall_.unix_time_ns() + kPeriodNs);
  in_period_ = 0;
  if (!flood) {
    protocol::Message status;
    status.header.type = protocol::MessageType::get_status;
    send(status);
    return;
  }
  for (std::size_t i = 0; i < SocketHandler::kBudget; ++i) send(next_heavy());
}

void WcetOperatorLoad::after() noexcept {
  for (std::size_t n = client_.receive_batch(Span<hal::UdpDatagram>(g_answers)); n > 0;
       n = client_.receive_batch(Span<hal::UdpDatagram>(g_answers))) {
    for (std::size_t i = 0; i < n; ++i) {
      ++answers_;
      const Result<protocol::FrameView> frame = protocol::parse_frame(ConstByteSpan(g_answers[i].bytes.data(), g_answers[i].size));
      if (!frame.ok() || frame.value().header.type != protocol::MessageType::sdo_result) continue;
      const Result<protocol::Message> result = protocol::decode_payload(frame.value().header, frame.value().payload);
      if (!result.ok() || result.value().sdo_result.status == protocol::SdoStatus::busy) continue;
      sdo_in_flight_ = false;  // the transfer ended (done, aborted, timed out, unreachable): the next may go
      sdo_done_ += result.value().sdo_result.status == protocol::SdoStatus::ok ? 1U : 0U;
      ++sdo_ended_;
    }
  }
}

__attribute__((noinline)) void wcet_socket_handler_period(SocketHandler& handler, hal::Nanoseconds now) noexcept {
  handler.step(now);
  mark_period_end("socket_handler");
}

}  // namespace rescue::app
