#include "drivers/sim/coe/coe_sdo_server.hpp"

#include <array>
#include <cstring>

#include "core/base/endian.hpp"
#include "drivers/sim/coe/coe_complete_access.hpp"
#include "drivers/sim/coe/coe_sdo_information.hpp"
#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/mailbox.hpp"

namespace rescue::drivers {
namespace {

namespace coe = ecat::coe;
namespace mbx = ecat::mbx;

std::size_t error_reply(ByteSpan response, std::uint16_t detail) noexcept {
  return mbx::encode_error_reply(response, 0, detail).value_or(0);
}

std::size_t send(ByteSpan response, std::uint8_t counter, const coe::Sdo& sdo) noexcept {
  mbx::Header h;
  h.counter = counter;
  auto n = coe::encode(response, h, sdo);
  // A response that does not fit SM1 becomes an abort, which always fits (16 bytes).
  if (!n.ok()) return coe::encode(response, h, coe::abort(sdo.index, sdo.subindex, coe::abort_code::kOutOfMemory)).value_or(0);
  return n.value();
}

constexpr std::size_t kInitiateOverhead = mbx::kHeaderSize + coe::kSdoInitiateSize;  // 16
constexpr std::size_t kSegmentOverhead = mbx::kHeaderSize + coe::kCoeHeaderSize + coe::kSegmentHeaderSize;  // 9

std::size_t upload(const coe::Sdo& req, const ObjectDictionary& od, ByteSpan response, std::uint8_t counter,
                   SdoSegmentState* segments) noexcept {
  const ObjectRead r = od.read(req.index, req.subindex);
  if (r.abort_code != 0) return send(response, counter, coe::abort(req.index, req.subindex, r.abort_code));
  const std::size_t room = response.size() > kInitiateOverhead ? response.size() - kInitiateOverhead : 0;
  if (segments == nullptr || r.bytes.size() <= coe::kMaxExpeditedSize || r.bytes.size() <= room) {
    return send(response, counter, coe::upload_response(req.index, req.subindex, r.bytes));
  }
  // Longer than SM1: the complete size and what fits, the rest in upload segments.
  coe::Sdo first = coe::upload_response(req.index, req.subindex, r.bytes.first(room));
  first.expedited = false;
  first.size = static_cast<std::uint32_t>(r.bytes.size());
  *segments = SdoSegmentState{};
  segments->active = true;
  segments->upload = true;
  segments->index = req.index;
  segments->subindex = req.subindex;
  segments->offset = room;
  segments->size = r.bytes.size();
  return send(response, counter, first);
}

std::size_t upload_segment(const coe::Sdo& req, const ObjectDictionary& od, ByteSpan response, std::uint8_t counter,
                           SdoSegmentState& st) noexcept {
  if (!st.active || !st.upload) return send(response, counter, coe::abort(0, 0, coe::abort_code::kUnknownCommand));
  if (req.toggle != st.toggle) {
    st.active = false;
    return send(response, counter, coe::abort(st.index, st.subindex, coe::abort_code::kToggleBit));
  }
  const ObjectRead r = od.read(st.index, st.subindex);
  if (r.abort_code != 0 || r.bytes.size() != st.size) {  // the value changed length meanwhile
    st.active = false;
    return send(response, counter, coe::abort(st.index, st.subindex, r.abort_code != 0 ? r.abort_code : coe::abort_code::kGeneralError));
  }
  const std::size_t room = response.size() > kSegmentOverhead ? response.size() - kSegmentOverhead : 0;
  const std::size_t left = st.size - st.offset;
  const std::size_t n = left < room ? left : room;
  coe::Sdo seg;
  seg.kind = coe::SdoKind::upload_segment_response;
  seg.toggle = st.toggle;
  seg.data = r.bytes.subspan(st.offset, n);
  st.offset += n;
  seg.last_segment = st.offset >= st.size;
  st.toggle = !st.toggle;
  if (seg.last_segment) st.active = false;
  return send(response, counter, seg);
}

std::size_t download_segment(const coe::Sdo& req, ObjectDictionary& od, ecat::reg::AlState state, ByteSpan response,
                             std::uint8_t counter, SdoSegmentState& st) noexcept {
  if (!st.active || st.upload) return send(response, counter, coe::abort(0, 0, coe::abort_code::kUnknownCommand));
  if (req.toggle != st.toggle) {
    st.active = false;
    return send(response, counter, coe::abort(st.index, st.subindex, coe::abort_code::kToggleBit));
  }
  if (st.offset + req.data.size() > st.size) {
    st.active = false;
    return send(response, counter, coe::abort(st.index, st.subindex, coe::abort_code::kLengthTooHigh));
  }
  if (!req.data.empty()) std::memcpy(st.buffer.data() + st.offset, req.data.data(), req.data.size());
  st.offset += req.data.size();
  coe::Sdo ack;
  ack.kind = coe::SdoKind::download_segment_response;
  ack.toggle = st.toggle;
  st.toggle = !st.toggle;
  if (!req.last_segment) return send(response, counter, ack);
  st.active = false;
  if (st.offset != st.size) return send(response, counter, coe::abort(st.index, st.subindex, coe::abort_code::kLengthTooLow));
  const std::uint32_t code = od.write(st.index, st.subindex, ConstByteSpan(st.buffer.data(), st.size), state);
  if (code != 0) return send(response, counter, coe::abort(st.index, st.subindex, code));
  return send(response, counter, ack);
}

std::size_t upload_complete(const coe::Sdo& req, const ObjectDictionary& od, ByteSpan response,
                            std::uint8_t counter) noexcept {
  constexpr std::size_t kOverhead = mbx::kHeaderSize + coe::kSdoInitiateSize;  // the u32 size is in the SDO part
  std::array<std::uint8_t, 512> object{};
  const std::size_t room = response.size() > kOverhead ? response.size() - kOverhead : 0;
  std::size_t length = 0;
  const std::uint32_t code =
      read_complete(od, req.index, req.subindex, ByteSpan(object.data(), room < object.size() ? room : object.size()), length);
  if (code != 0) return send(response, counter, coe::abort(req.index, req.subindex, code));
  // Always a normal transfer, with the complete-access bit mirrored (0x51), as slaves answer.
  coe::Sdo r = coe::upload_response(req.index, req.subindex, ConstByteSpan(object.data(), length));
  r.expedited = false;
  r.size_indicated = true;
  r.size = static_cast<std::uint32_t>(length);
  r.complete_access = true;
  return send(response, counter, r);
}

std::size_t download(const coe::Sdo& req, ObjectDictionary& od, ecat::reg::AlState state, ByteSpan response,
                     std::uint8_t counter, SdoSegmentState* segments) noexcept {
  // A normal transfer announcing more than it carries continues in segments.
  if (!req.expedited && req.size_indicated && req.size != req.data.size()) {
    if (segments == nullptr || req.complete_access || req.size < req.data.size()) {
      return send(response, counter, coe::abort(req.index, req.subindex, coe::abort_code::kUnsupportedAccess));
    }
    const ObjectEntry* e = od.find(req.index, req.subindex);
    if (e == nullptr) return send(response, counter, coe::abort(req.index, req.subindex, coe::abort_code::kObjectDoesNotExist));
    if (req.size > e->size || req.size > SdoSegmentState::kCapacity) {
      return send(response, counter, coe::abort(req.index, req.subindex, coe::abort_code::kLengthTooHigh));
    }
    *segments = SdoSegmentState{};
    segments->active = true;
    segments->index = req.index;
    segments->subindex = req.subindex;
    segments->size = req.size;
    if (!req.data.empty()) std::memcpy(segments->buffer.data(), req.data.data(), req.data.size());
    segments->offset = req.data.size();
    return send(response, counter, coe::download_response(req.index, req.subindex));
  }
  ConstByteSpan value = req.data;
  if (req.expedited && !req.size_indicated) {
    // Size not indicated: the object's own size out of the 4 bytes.
    const ObjectEntry* e = od.find(req.index, req.subindex);
    if (e != nullptr && e->size < value.size()) value = value.first(e->size);
  }
  const std::uint32_t code = req.complete_access ? write_complete(od, req.index, req.subindex, value, state)
                                                 : od.write(req.index, req.subindex, value, state);
  if (code != 0) return send(response, counter, coe::abort(req.index, req.subindex, code));
  return send(response, counter, coe::download_response(req.index, req.subindex));
}

}  // namespace

std::size_t serve_sdo(ConstByteSpan request, ObjectDictionary& od, ecat::reg::AlState state, ByteSpan response,
                      std::uint8_t counter, SdoSegmentState* segments) noexcept {
  auto m = mbx::decode(request);
  if (!m.ok()) return error_reply(response, request.size() < mbx::kHeaderSize ? mbx::error_code::kSizeTooShort : mbx::error_code::kInvalidSize);
  if (m.value().header.type != mbx::Type::coe) return error_reply(response, mbx::error_code::kUnsupportedProtocol);
  auto c = coe::decode(request);
  if (!c.ok()) {
    if (c.error().code == Errc::unsupported) {
      // A command specifier this server does not know (block transfer): abort that object.
      const ConstByteSpan data = m.value().data;
      const std::uint16_t index = data.size() >= 5 ? load_le16(data.data() + 3) : 0;
      const std::uint8_t sub = data.size() >= 6 ? data[5] : 0;
      return send(response, counter, coe::abort(index, sub, coe::abort_code::kUnknownCommand));
    }
    return error_reply(response, mbx::error_code::kSizeTooShort);
  }
  const coe::Message& msg = c.value();
  if (msg.service == coe::Service::sdo_information) return serve_sdo_information(msg.payload, od, response, counter, 0).length;
  if (msg.service != coe::Service::sdo_request) return error_reply(response, mbx::error_code::kServiceNotSupported);
  const coe::Sdo& sdo = msg.sdo;
  switch (sdo.kind) {
    case coe::SdoKind::upload_initiate_request:
      if (segments != nullptr) segments->active = false;  // a new transfer ends any old one
      return sdo.complete_access ? upload_complete(sdo, od, response, counter) : upload(sdo, od, response, counter, segments);
    case coe::SdoKind::download_initiate_request:
      if (segments != nullptr) segments->active = false;
      return download(sdo, od, state, response, counter, segments);
    case coe::SdoKind::upload_segment_request:
      if (segments != nullptr) return upload_segment(sdo, od, response, counter, *segments);
      break;
    case coe::SdoKind::download_segment_request:
      if (segments != nullptr) return download_segment(sdo, od, state, response, counter, *segments);
      break;
    case coe::SdoKind::abort:
      if (segments != nullptr) segments->active = false;
      return 0;  // the master gave up a transfer: nothing to answer
    default: break;
  }
  return send(response, counter, coe::abort(0, 0, coe::abort_code::kUnknownCommand));
}

std::size_t serve_sdo_fragment(ConstByteSpan request, const ObjectDictionary& od, ByteSpan response,
                               std::uint8_t counter, std::uint16_t fragment) noexcept {
  if (fragment == 0) return 0;
  auto c = coe::decode(request);
  if (!c.ok() || c.value().service != coe::Service::sdo_information) return 0;
  return serve_sdo_information(c.value().payload, od, response, counter, fragment).length;
}

}  // namespace rescue::drivers
