#include "ecat/mailbox/coe.hpp"

#include <cstring>

#include "core/base/endian.hpp"

namespace rescue::ecat::coe {
namespace {

std::uint32_t u32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

// Command specifiers (bits 7..5 of the command byte).
constexpr std::uint8_t kCcsDownloadSegment = 0;
constexpr std::uint8_t kCcsDownloadInitiate = 1;
constexpr std::uint8_t kCcsUploadInitiate = 2;
constexpr std::uint8_t kCcsUploadSegment = 3;
constexpr std::uint8_t kScsUploadSegment = 0;
constexpr std::uint8_t kScsDownloadSegment = 1;
constexpr std::uint8_t kScsUploadInitiate = 2;
constexpr std::uint8_t kScsDownloadInitiate = 3;
constexpr std::uint8_t kCsAbort = 4;

constexpr std::uint8_t kBitSizeIndicated = 0x01;
constexpr std::uint8_t kBitExpedited = 0x02;
constexpr std::uint8_t kBitCompleteAccess = 0x10;
constexpr std::uint8_t kBitToggle = 0x10;
constexpr std::uint8_t kBitLastSegment = 0x01;

// Initiate layout shared by download requests and upload responses: n/e/s bits, then either
// the expedited bytes in 4..7 or the complete size in 4..7 followed by data.
void decode_initiate_data(ConstByteSpan b, std::uint8_t command, Sdo& sdo) noexcept {
  sdo.expedited = (command & kBitExpedited) != 0;
  sdo.size_indicated = (command & kBitSizeIndicated) != 0;
  if (sdo.expedited) {
    const std::uint32_t unused = (command >> 2U) & 0x03U;
    sdo.size = sdo.size_indicated ? 4U - unused : 4U;  // without size: the whole 4 bytes
    sdo.data = b.subspan(4, sdo.size);
    return;
  }
  sdo.size = load_le32(b.data() + 4);
  const std::size_t present = b.size() - kSdoHeaderSize;
  // Bytes past the complete size are padding; fewer bytes mean segments follow.
  sdo.data = b.subspan(kSdoHeaderSize, sdo.size_indicated && sdo.size < present ? sdo.size : present);
}

// Segment layout shared by download segment requests and upload segment responses.
void decode_segment_data(ConstByteSpan b, std::uint8_t command, Sdo& sdo) noexcept {
  sdo.toggle = (command & kBitToggle) != 0;
  sdo.last_segment = (command & kBitLastSegment) != 0;
  std::size_t length = b.size() - kSegmentHeaderSize;
  // n counts the unused bytes of a minimum (7-byte) segment only.
  if (length == kMinSegmentData) length -= (command >> 1U) & 0x07U;
  sdo.data = b.subspan(kSegmentHeaderSize, length);
}

void put_header(std::uint8_t* p, std::uint8_t command, std::uint16_t index, std::uint8_t subindex) noexcept {
  p[0] = command;
  store_le16(p + 1, index);
  p[3] = subindex;
}

}  // namespace

namespace {

// The kind a command specifier names in a request (client) or response (server) SDO.
Result<SdoKind> kind_of(std::uint8_t cs, Service service) noexcept {
  if (cs == kCsAbort) return SdoKind::abort;
  if (service == Service::sdo_request) {
    switch (cs) {
      case kCcsDownloadInitiate: return SdoKind::download_initiate_request;
      case kCcsUploadInitiate: return SdoKind::upload_initiate_request;
      case kCcsDownloadSegment: return SdoKind::download_segment_request;
      case kCcsUploadSegment: return SdoKind::upload_segment_request;
      default: return make_error(Errc::unsupported, "sdo command", cs);  // block transfers
    }
  }
  if (service == Service::sdo_response) {
    switch (cs) {
      case kScsUploadInitiate: return SdoKind::upload_initiate_response;
      case kScsDownloadInitiate: return SdoKind::download_initiate_response;
      case kScsUploadSegment: return SdoKind::upload_segment_response;
      case kScsDownloadSegment: return SdoKind::download_segment_response;
      default: return make_error(Errc::unsupported, "sdo command", cs);
    }
  }
  return make_error(Errc::invalid_argument, "not an sdo service", static_cast<std::uint32_t>(service));
}

}  // namespace

Result<Sdo> decode_sdo(ConstByteSpan sdo_bytes, Service service) noexcept {
  const ConstByteSpan b = sdo_bytes;
  if (b.size() < kSdoHeaderSize) return make_error(Errc::truncated, "sdo header", 0, u32(b.size()));
  const std::uint8_t command = b[0];
  auto kind = kind_of(static_cast<std::uint8_t>(command >> 5U), service);
  if (!kind.ok()) return kind.error();
  Sdo sdo;
  sdo.kind = kind.value();
  switch (sdo.kind) {
    case SdoKind::download_segment_request:
    case SdoKind::upload_segment_response: decode_segment_data(b, command, sdo); return sdo;
    case SdoKind::upload_segment_request:
    case SdoKind::download_segment_response: sdo.toggle = (command & kBitToggle) != 0; return sdo;
    default: break;  // the rest address an object
  }
  sdo.index = load_le16(b.data() + 1);
  sdo.subindex = b[3];
  switch (sdo.kind) {
    case SdoKind::abort: sdo.abort_code = load_le32(b.data() + 4); break;
    case SdoKind::download_initiate_request:
      sdo.complete_access = (command & kBitCompleteAccess) != 0;
      decode_initiate_data(b, command, sdo);
      break;
    case SdoKind::upload_initiate_request: sdo.complete_access = (command & kBitCompleteAccess) != 0; break;
    case SdoKind::upload_initiate_response:
      sdo.complete_access = (command & kBitCompleteAccess) != 0;
      decode_initiate_data(b, command, sdo);
      break;
    default: break;  // download initiate response: index and subindex only
  }
  return sdo;
}

Result<Message> decode(ConstByteSpan mailbox) noexcept {
  auto m = mbx::decode(mailbox);
  if (!m.ok()) return m.error();
  Message msg;
  msg.mailbox = m.value().header;
  if (msg.mailbox.type != mbx::Type::coe) {
    return make_error(Errc::unsupported, "not a CoE mailbox", static_cast<std::uint32_t>(msg.mailbox.type));
  }
  const ConstByteSpan data = m.value().data;
  if (data.size() < kCoeHeaderSize) return make_error(Errc::truncated, "coe header", 0, u32(data.size()));
  const std::uint16_t coe = load_le16(data.data());
  msg.number = static_cast<std::uint16_t>(coe & 0x01FFU);
  msg.service = static_cast<Service>(coe >> 12U);
  msg.payload = data.subspan(kCoeHeaderSize, data.size() - kCoeHeaderSize);
  switch (msg.service) {
    case Service::sdo_request:
    case Service::sdo_response: {
      auto sdo = decode_sdo(msg.payload, msg.service);
      if (!sdo.ok()) return sdo.error();
      msg.sdo = sdo.value();
      return msg;
    }
    case Service::emergency:
      if (msg.payload.size() < 8) return make_error(Errc::truncated, "emergency", 0, u32(msg.payload.size()));
      msg.emergency.error_code = load_le16(msg.payload.data());
      msg.emergency.error_register = msg.payload[2];
      std::memcpy(msg.emergency.manufacturer, msg.payload.data() + 3, sizeof msg.emergency.manufacturer);
      return msg;
    default: return msg;  // PDO and SDO information services: payload only
  }
}

Result<std::size_t> encode(ByteSpan out, const mbx::Header& mailbox, const Sdo& sdo) noexcept {
  // Largest message first: compute the CoE data length, check the buffer, then write.
  std::size_t sdo_length = kSdoHeaderSize;
  const bool segment_with_data = sdo.kind == SdoKind::download_segment_request || sdo.kind == SdoKind::upload_segment_response;
  const bool initiate_with_data = sdo.kind == SdoKind::download_initiate_request || sdo.kind == SdoKind::upload_initiate_response;
  if (initiate_with_data) {
    if (sdo.expedited && (sdo.data.empty() || sdo.data.size() > kMaxExpeditedSize)) {
      return make_error(Errc::invalid_argument, "sdo expedited size", u32(sdo.data.size()));
    }
    if (!sdo.expedited) sdo_length += sdo.data.size();
  } else if (segment_with_data) {
    sdo_length = kSegmentHeaderSize + (sdo.data.size() < kMinSegmentData ? kMinSegmentData : sdo.data.size());
  }
  const std::size_t coe_length = kCoeHeaderSize + sdo_length;
  if (coe_length > 0xFFFF) return make_error(Errc::invalid_argument, "sdo too long", u32(coe_length));

  mbx::Header h = mailbox;
  h.type = mbx::Type::coe;
  h.length = static_cast<std::uint16_t>(coe_length);
  RESCUE_TRY(mbx::encode_header(out, h));

  std::uint8_t* p = out.data() + mbx::kHeaderSize;
  const Service service = (is_request(sdo.kind) || sdo.kind == SdoKind::abort) ? Service::sdo_request : Service::sdo_response;
  store_le16(p, static_cast<std::uint16_t>(static_cast<unsigned>(service) << 12U));
  p += kCoeHeaderSize;
  std::memset(p, 0, sdo_length);

  const std::uint8_t toggle = sdo.toggle ? kBitToggle : 0;
  switch (sdo.kind) {
    case SdoKind::download_initiate_request:
    case SdoKind::upload_initiate_response: {
      const std::uint8_t cs = sdo.kind == SdoKind::download_initiate_request ? kCcsDownloadInitiate : kScsUploadInitiate;
      auto command = static_cast<std::uint8_t>(cs << 5U);
      // Complete access is marked in the download request and, mirrored, in the upload response.
      if (sdo.complete_access) command |= kBitCompleteAccess;
      if (sdo.expedited) {
        command = static_cast<std::uint8_t>(command | ((kMaxExpeditedSize - sdo.data.size()) << 2U) | kBitExpedited | kBitSizeIndicated);
        put_header(p, command, sdo.index, sdo.subindex);
        std::memcpy(p + 4, sdo.data.data(), sdo.data.size());
      } else {
        command |= kBitSizeIndicated;
        put_header(p, command, sdo.index, sdo.subindex);
        store_le32(p + 4, sdo.size != 0 ? sdo.size : u32(sdo.data.size()));
        if (!sdo.data.empty()) std::memcpy(p + kSdoHeaderSize, sdo.data.data(), sdo.data.size());
      }
      break;
    }
    case SdoKind::download_initiate_response:
      put_header(p, static_cast<std::uint8_t>(kScsDownloadInitiate << 5U), sdo.index, sdo.subindex);
      break;
    case SdoKind::upload_initiate_request:
      put_header(p, static_cast<std::uint8_t>((kCcsUploadInitiate << 5U) | (sdo.complete_access ? kBitCompleteAccess : 0)),
                 sdo.index, sdo.subindex);
      break;
    case SdoKind::download_segment_request:
    case SdoKind::upload_segment_response: {
      // Both directions' data segments have specifier 0 (kCcsDownloadSegment, kScsUploadSegment),
      // so the command byte is only toggle, unused-byte count and last-segment flag.
      const std::size_t unused = sdo.data.size() < kMinSegmentData ? kMinSegmentData - sdo.data.size() : std::size_t{0};
      const unsigned last = sdo.last_segment ? kBitLastSegment : 0U;
      p[0] = static_cast<std::uint8_t>(toggle | (static_cast<unsigned>(unused) << 1U) | last);
      if (!sdo.data.empty()) std::memcpy(p + 1, sdo.data.data(), sdo.data.size());
      break;
    }
    case SdoKind::download_segment_response: p[0] = static_cast<std::uint8_t>((kScsDownloadSegment << 5U) | toggle); break;
    case SdoKind::upload_segment_request: p[0] = static_cast<std::uint8_t>((kCcsUploadSegment << 5U) | toggle); break;
    case SdoKind::abort:
      put_header(p, static_cast<std::uint8_t>(kCsAbort << 5U), sdo.index, sdo.subindex);
      store_le32(p + 4, sdo.abort_code);
      break;
  }
  return mbx::kHeaderSize + coe_length;
}

Sdo upload_request(std::uint16_t index, std::uint8_t subindex, bool complete_access) noexcept {
  Sdo s;
  s.kind = SdoKind::upload_initiate_request;
  s.index = index;
  s.subindex = subindex;
  s.complete_access = complete_access;
  return s;
}

namespace {
Sdo initiate_with_data(SdoKind kind, std::uint16_t index, std::uint8_t subindex, ConstByteSpan data) noexcept {
  Sdo s;
  s.kind = kind;
  s.index = index;
  s.subindex = subindex;
  s.expedited = !data.empty() && data.size() <= kMaxExpeditedSize;
  s.size_indicated = true;
  s.size = u32(data.size());
  s.data = data;
  return s;
}
}  // namespace

Sdo download_request(std::uint16_t index, std::uint8_t subindex, ConstByteSpan data) noexcept {
  return initiate_with_data(SdoKind::download_initiate_request, index, subindex, data);
}

Sdo upload_response(std::uint16_t index, std::uint8_t subindex, ConstByteSpan data) noexcept {
  return initiate_with_data(SdoKind::upload_initiate_response, index, subindex, data);
}

Sdo download_response(std::uint16_t index, std::uint8_t subindex) noexcept {
  Sdo s;
  s.kind = SdoKind::download_initiate_response;
  s.index = index;
  s.subindex = subindex;
  return s;
}

Sdo abort(std::uint16_t index, std::uint8_t subindex, std::uint32_t code) noexcept {
  Sdo s;
  s.kind = SdoKind::abort;
  s.index = index;
  s.subindex = subindex;
  s.abort_code = code;
  return s;
}

const char* to_string(SdoKind kind) noexcept {
  switch (kind) {
    case SdoKind::download_initiate_request: return "download initiate request";
    case SdoKind::download_initiate_response: return "download initiate response";
    case SdoKind::download_segment_request: return "download segment request";
    case SdoKind::download_segment_response: return "download segment response";
    case SdoKind::upload_initiate_request: return "upload initiate request";
    case SdoKind::upload_initiate_response: return "upload initiate response";
    case SdoKind::upload_segment_request: return "upload segment request";
    case SdoKind::upload_segment_response: return "upload segment response";
    case SdoKind::abort: return "abort";
  }
  return "?";
}

const char* explain_abort_code(std::uint32_t code) noexcept {
  switch (code) {
    case abort_code::kToggleBit: return "toggle bit not alternated";
    case abort_code::kTimeout: return "SDO protocol timed out";
    case abort_code::kUnknownCommand: return "client/server command specifier not valid or unknown";
    case abort_code::kOutOfMemory: return "out of memory";
    case abort_code::kUnsupportedAccess: return "unsupported access to an object";
    case abort_code::kWriteOnly: return "attempt to read a write-only object";
    case abort_code::kReadOnly: return "attempt to write a read-only object";
    case abort_code::kSubindex0MustBeZero: return "subindex cannot be written, subindex 0 must be 0 for write access";
    case abort_code::kCompleteAccessUnsupported: return "complete access not supported for this object";
    case abort_code::kObjectDoesNotExist: return "object does not exist in the object dictionary";
    case abort_code::kCannotBeMapped: return "object cannot be mapped to the PDO";
    case abort_code::kPdoLengthExceeded: return "number and length of mapped objects would exceed the PDO length";
    case abort_code::kParameterIncompatible: return "general parameter incompatibility";
    case abort_code::kDeviceIncompatible: return "general internal incompatibility in the device";
    case abort_code::kHardwareError: return "access failed due to a hardware error";
    case abort_code::kLengthMismatch: return "data type does not match, length of service parameter does not match";
    case abort_code::kLengthTooHigh: return "data type does not match, length of service parameter too high";
    case abort_code::kLengthTooLow: return "data type does not match, length of service parameter too low";
    case abort_code::kSubindexDoesNotExist: return "subindex does not exist";
    case abort_code::kValueRange: return "value range of parameter exceeded";
    case abort_code::kValueTooHigh: return "value of parameter written too high";
    case abort_code::kValueTooLow: return "value of parameter written too low";
    case abort_code::kMaxBelowMin: return "maximum value is less than minimum value";
    case abort_code::kGeneralError: return "general error";
    case abort_code::kCannotTransfer: return "data cannot be transferred or stored to the application";
    case abort_code::kCannotTransferLocalControl: return "data cannot be transferred because of local control";
    case abort_code::kCannotTransferInState: return "data cannot be transferred in the present device state";
    case abort_code::kNoObjectDictionary: return "no object dictionary present";
    default: return "unknown abort code";
  }
}

}  // namespace rescue::ecat::coe
