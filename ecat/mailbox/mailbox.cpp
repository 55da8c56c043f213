#include "ecat/mailbox/mailbox.hpp"

#include "core/base/endian.hpp"

namespace rescue::ecat::mbx {
namespace {

constexpr std::uint16_t kErrorReplyType = 0x0001;  // "mailbox command"

std::uint32_t u32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

}  // namespace

Result<Message> decode(ConstByteSpan bytes) noexcept {
  if (bytes.size() < kHeaderSize) return make_error(Errc::truncated, "mailbox header", 0, u32(bytes.size()));
  const std::uint8_t* p = bytes.data();
  Message m;
  m.header.length = load_le16(p);
  m.header.address = load_le16(p + 2);
  m.header.channel = static_cast<std::uint8_t>(p[4] & 0x3FU);
  m.header.priority = static_cast<std::uint8_t>(p[4] >> 6U);
  m.header.type = static_cast<Type>(p[5] & 0x0FU);
  m.header.counter = static_cast<std::uint8_t>((p[5] >> 4U) & 0x07U);
  const std::size_t available = bytes.size() - kHeaderSize;
  if (m.header.length > available) return make_error(Errc::truncated, "mailbox length", m.header.length, u32(available));
  m.data = bytes.subspan(kHeaderSize, m.header.length);
  return m;
}

Status encode_header(ByteSpan out, const Header& header) noexcept {
  if (header.channel > 0x3F || header.priority > 3 || header.counter > 7 || static_cast<std::uint8_t>(header.type) > 0x0F) {
    return make_error(Errc::invalid_argument, "mailbox header field", header.channel, header.counter);
  }
  if (out.size() < kHeaderSize || out.size() - kHeaderSize < header.length) {
    return make_error(Errc::capacity_exceeded, "mailbox too small", header.length, u32(out.size()));
  }
  std::uint8_t* p = out.data();
  store_le16(p, header.length);
  store_le16(p + 2, header.address);
  p[4] = static_cast<std::uint8_t>(header.channel | (header.priority << 6U));
  p[5] = static_cast<std::uint8_t>(static_cast<std::uint8_t>(header.type) | (header.counter << 4U));
  return Status::success();
}

Result<std::size_t> encode_error_reply(ByteSpan out, std::uint16_t address, std::uint16_t detail) noexcept {
  Header h;
  h.length = kErrorReplyLength;
  h.address = address;
  h.type = Type::error;
  RESCUE_TRY(encode_header(out, h));
  store_le16(out.data() + kHeaderSize, kErrorReplyType);
  store_le16(out.data() + kHeaderSize + 2, detail);
  return kHeaderSize + kErrorReplyLength;
}

Result<std::uint16_t> decode_error_reply(const Message& message) noexcept {
  if (message.header.type != Type::error) return make_error(Errc::malformed, "not a mailbox error reply");
  if (message.data.size() < kErrorReplyLength) return make_error(Errc::truncated, "mailbox error reply", 0, u32(message.data.size()));
  return load_le16(message.data.data() + 2);
}

const char* to_string(Type type) noexcept {
  switch (type) {
    case Type::error: return "ERR";
    case Type::aoe: return "AoE";
    case Type::eoe: return "EoE";
    case Type::coe: return "CoE";
    case Type::foe: return "FoE";
    case Type::soe: return "SoE";
    case Type::voe: return "VoE";
  }
  return "?";
}

const char* explain_error_code(std::uint16_t detail) noexcept {
  switch (detail) {
    case error_code::kSyntax: return "syntax of the mailbox header is wrong";
    case error_code::kUnsupportedProtocol: return "mailbox protocol not supported";
    case error_code::kInvalidChannel: return "channel field invalid";
    case error_code::kServiceNotSupported: return "service in the mailbox protocol not supported";
    case error_code::kInvalidHeader: return "protocol header of the mailbox data invalid";
    case error_code::kSizeTooShort: return "mailbox data too short";
    case error_code::kNoMoreMemory: return "no memory to answer the request";
    case error_code::kInvalidSize: return "length of the data inconsistent";
    default: return "unknown mailbox error";
  }
}

}  // namespace rescue::ecat::mbx
