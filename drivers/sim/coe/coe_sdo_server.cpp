#include "drivers/sim/coe/coe_sdo_server.hpp"

#include <array>

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

std::size_t upload(const coe::Sdo& req, const ObjectDictionary& od, ByteSpan response, std::uint8_t counter) noexcept {
  const ObjectRead r = od.read(req.index, req.subindex);
  if (r.abort_code != 0) return send(response, counter, coe::abort(req.index, req.subindex, r.abort_code));
  return send(response, counter, coe::upload_response(req.index, req.subindex, r.bytes));
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
                     std::uint8_t counter) noexcept {
  // A normal transfer announcing more than it carries would continue in segments.
  if (!req.expedited && req.size_indicated && req.size != req.data.size()) {
    return send(response, counter, coe::abort(req.index, req.subindex, coe::abort_code::kUnsupportedAccess));
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
                      std::uint8_t counter) noexcept {
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
      return sdo.complete_access ? upload_complete(sdo, od, response, counter) : upload(sdo, od, response, counter);
    case coe::SdoKind::download_initiate_request: return download(sdo, od, state, response, counter);
    case coe::SdoKind::abort: return 0;  // the master gave up a transfer: nothing to answer
    default: return send(response, counter, coe::abort(0, 0, coe::abort_code::kUnknownCommand));
  }
}

std::size_t serve_sdo_fragment(ConstByteSpan request, const ObjectDictionary& od, ByteSpan response,
                               std::uint8_t counter, std::uint16_t fragment) noexcept {
  if (fragment == 0) return 0;
  auto c = coe::decode(request);
  if (!c.ok() || c.value().service != coe::Service::sdo_information) return 0;
  return serve_sdo_information(c.value().payload, od, response, counter, fragment).length;
}

}  // namespace rescue::drivers
