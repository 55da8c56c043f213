#include "ecat/mailbox/coe_information.hpp"

#include "core/base/le_stream.hpp"
#include "ecat/mailbox/coe.hpp"

namespace rescue::ecat::coe::info {
namespace {

std::uint32_t u32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

}  // namespace

Result<Fragment> decode_fragment(ConstByteSpan coe_payload) noexcept {
  if (coe_payload.size() < kInfoHeaderSize) {
    return make_error(Errc::truncated, "sdo information header", u32(coe_payload.size()), u32(kInfoHeaderSize));
  }
  LeReader in(coe_payload);
  Fragment f;
  const std::uint8_t opcode = in.u8();
  f.opcode = static_cast<std::uint8_t>(opcode & kOpcodeMask);
  f.incomplete = (opcode & kIncomplete) != 0;
  (void)in.u8();  // reserved
  f.fragments_left = in.u16();
  f.data = coe_payload.subspan(kInfoHeaderSize, coe_payload.size() - kInfoHeaderSize);
  return f;
}

Result<std::size_t> encode_request(ByteSpan out, const mbx::Header& mailbox, std::uint8_t opcode, std::uint16_t index,
                                   std::uint8_t subindex) noexcept {
  std::size_t data = 0;
  switch (opcode) {
    case kGetOdListRequest:
    case kGetObjectDescriptionRequest: data = 2; break;
    case kGetEntryDescriptionRequest: data = 4; break;
    default: return make_error(Errc::invalid_argument, "sdo information request opcode", opcode);
  }
  mbx::Header h = mailbox;
  h.type = mbx::Type::coe;
  h.length = static_cast<std::uint16_t>(kCoeHeaderSize + kInfoHeaderSize + data);
  const std::size_t total = mbx::kHeaderSize + h.length;
  if (out.size() < total) return make_error(Errc::capacity_exceeded, "sdo information request", u32(out.size()), u32(total));
  RESCUE_TRY(mbx::encode_header(out, h));
  LeWriter w(out.subspan(mbx::kHeaderSize, total - mbx::kHeaderSize));
  w.u16(static_cast<std::uint16_t>(static_cast<unsigned>(Service::sdo_information) << 12U));
  w.u8(opcode);
  w.u8(0);   // reserved
  w.u16(0);  // fragments left: a request is one fragment
  w.u16(index);
  if (opcode == kGetEntryDescriptionRequest) {
    w.u8(subindex);
    w.u8(0);  // value info: the name only
  }
  if (!w.ok()) return make_error(Errc::capacity_exceeded, "sdo information request");
  return total;
}

Result<ObjectDescription> decode_object_description(ConstByteSpan data) noexcept {
  if (data.size() < kObjectDescriptionHead) {
    return make_error(Errc::truncated, "object description", u32(data.size()), u32(kObjectDescriptionHead));
  }
  LeReader in(data);
  ObjectDescription d;
  d.index = in.u16();
  d.data_type = in.u16();
  d.max_subindex = in.u8();
  d.object_code = in.u8();
  d.name = data.subspan(kObjectDescriptionHead, data.size() - kObjectDescriptionHead);
  return d;
}

Result<EntryDescription> decode_entry_description(ConstByteSpan data) noexcept {
  if (data.size() < kEntryDescriptionHead) {
    return make_error(Errc::truncated, "entry description", u32(data.size()), u32(kEntryDescriptionHead));
  }
  LeReader in(data);
  EntryDescription e;
  e.index = in.u16();
  e.subindex = in.u8();
  e.value_info = in.u8();
  e.data_type = in.u16();
  e.bit_length = in.u16();
  e.access = in.u16();
  e.name = data.subspan(kEntryDescriptionHead, data.size() - kEntryDescriptionHead);
  return e;
}

std::uint16_t OdList::index(std::size_t i) const noexcept {
  if (i >= count || 2 * i + 1 >= indexes.size()) return 0;
  return static_cast<std::uint16_t>(indexes[2 * i] | (indexes[2 * i + 1] << 8U));
}

Result<OdList> decode_od_list(ConstByteSpan data) noexcept {
  if (data.size() < 2) return make_error(Errc::truncated, "od list", u32(data.size()), 2);
  if (data.size() % 2 != 0) return make_error(Errc::malformed, "od list length", u32(data.size()));
  OdList list;
  LeReader in(data);
  list.list_type = in.u16();
  list.indexes = data.subspan(2, data.size() - 2);
  list.count = list.indexes.size() / 2;
  return list;
}

const char* object_code_name(std::uint8_t code) noexcept {
  switch (code) {
    case 7: return "VAR";
    case 8: return "ARRAY";
    case 9: return "RECORD";
    default: return "?";
  }
}

const char* data_type_name(std::uint16_t type) noexcept {
  switch (type) {
    case 0x0001: return "BOOLEAN";
    case 0x0002: return "INTEGER8";
    case 0x0003: return "INTEGER16";
    case 0x0004: return "INTEGER32";
    case 0x0005: return "UNSIGNED8";
    case 0x0006: return "UNSIGNED16";
    case 0x0007: return "UNSIGNED32";
    case 0x0008: return "REAL32";
    case 0x0009: return "VISIBLE_STRING";
    case 0x000A: return "OCTET_STRING";
    case 0x000B: return "UNICODE_STRING";
    case 0x000F: return "DOMAIN";
    case 0x0010: return "INTEGER24";
    case 0x0011: return "REAL64";
    case 0x0015: return "INTEGER64";
    case 0x0016: return "UNSIGNED24";
    case 0x001B: return "UNSIGNED64";
    case 0x0021: return "PDO_MAPPING";
    case 0x0023: return "IDENTITY";
    default: return "?";
  }
}

void access_text(std::uint16_t access, char (&out)[7]) noexcept {
  for (std::size_t state = 0; state < 3; ++state) {
    out[2 * state] = (access & (1U << state)) != 0 ? 'r' : '-';
    out[2 * state + 1] = (access & (1U << (state + 3))) != 0 ? 'w' : '-';
  }
  out[6] = '\0';
}

}  // namespace rescue::ecat::coe::info
