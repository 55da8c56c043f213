#include "drivers/sim/coe/coe_sdo_information.hpp"

#include <algorithm>
#include <cstring>

#include "core/base/endian.hpp"
#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/mailbox.hpp"

namespace rescue::drivers {
namespace {

namespace mbx = ecat::mbx;
namespace coe = ecat::coe;
namespace abort_code = ecat::coe::abort_code;

constexpr std::size_t kInfoHeaderSize = 4;  // opcode, reserved, fragments left
constexpr std::size_t kPrefixSize = mbx::kHeaderSize + coe::kCoeHeaderSize + kInfoHeaderSize;
constexpr std::uint16_t kCoeSdoInformation = static_cast<std::uint16_t>(coe::Service::sdo_information) << 12U;
constexpr std::uint16_t kDataTypePdoMapping = 0x0021;
constexpr std::uint16_t kDataTypeIdentity = 0x0023;

enum ListType : std::uint16_t { kLengths = 0, kAll = 1, kRxMappable = 2, kTxMappable = 3, kBackup = 4, kSettings = 5 };
constexpr std::uint16_t kListTypes = 5;

bool in_range(std::uint16_t index, std::uint16_t first, std::uint16_t last) noexcept { return index >= first && index <= last; }

// Whether the PDO mapping objects in [first, last] map (index, subindex); subindex 0xFF: any.
bool mapped_by(const ObjectDictionary& od, std::uint16_t first, std::uint16_t last, std::uint16_t index,
               std::uint8_t subindex) noexcept {
  const auto maps = [&](const ObjectEntry& e) {
    if (!in_range(e.index, first, last) || e.subindex == 0 || e.size != 4) return false;
    const ObjectRead count = od.read(e.index, 0);
    if (count.abort_code != 0 || count.bytes.empty() || e.subindex > count.bytes[0]) return false;
    const ObjectRead value = od.read(e.index, e.subindex);
    if (value.abort_code != 0 || value.bytes.size() != 4) return false;
    const std::uint32_t mapping = load_le32(value.bytes.data());
    const auto mapped_index = static_cast<std::uint16_t>(mapping >> 16U);
    const auto mapped_sub = static_cast<std::uint8_t>(mapping >> 8U);
    return mapped_index == index && (subindex == 0xFF || mapped_sub == subindex);
  };
  return std::any_of(od.entries().begin(), od.entries().end(), maps);
}

bool rx_mappable(const ObjectDictionary& od, std::uint16_t index, std::uint8_t sub) noexcept {
  return mapped_by(od, 0x1600, 0x17FF, index, sub);
}
bool tx_mappable(const ObjectDictionary& od, std::uint16_t index, std::uint8_t sub) noexcept {
  return mapped_by(od, 0x1A00, 0x1BFF, index, sub);
}

bool in_list(const ObjectDictionary& od, std::uint16_t index, std::uint16_t list) noexcept {
  switch (list) {
    case kAll: return true;
    case kRxMappable: return rx_mappable(od, index, 0xFF);
    case kTxMappable: return tx_mappable(od, index, 0xFF);
    default: return false;  // no backup or startup parameters in these devices
  }
}

// Calls f(index) for each object of `list`, ascending (entries are sorted by index).
template <typename F>
void for_each_index(const ObjectDictionary& od, std::uint16_t list, F&& f) noexcept {
  bool first = true;
  std::uint16_t previous = 0;
  for (const ObjectEntry& e : od.entries()) {
    if (!first && e.index == previous) continue;
    first = false;
    previous = e.index;
    if (in_list(od, e.index, list)) f(e.index);
  }
}

std::uint16_t list_length(const ObjectDictionary& od, std::uint16_t list) noexcept {
  std::uint16_t n = 0;
  for_each_index(od, list, [&](std::uint16_t) { ++n; });
  return n;
}

// Writes the mailbox header, CoE header and SDO Information header; returns where data starts.
std::uint8_t* begin_reply(ByteSpan response, std::uint8_t counter, std::uint8_t opcode, std::uint16_t fragments_left,
                          std::size_t data_length) noexcept {
  mbx::Header h;
  h.type = mbx::Type::coe;
  h.counter = counter;
  h.length = static_cast<std::uint16_t>(coe::kCoeHeaderSize + kInfoHeaderSize + data_length);
  if (!mbx::encode_header(response, h).ok()) return nullptr;
  std::uint8_t* p = response.data() + mbx::kHeaderSize;
  store_le16(p, kCoeSdoInformation);
  p[2] = static_cast<std::uint8_t>(opcode | (fragments_left != 0 ? sdo_info::kIncomplete : 0U));
  p[3] = 0;
  store_le16(p + 4, fragments_left);
  return p + coe::kCoeHeaderSize + kInfoHeaderSize;
}

SdoInformationReply error_request(ByteSpan response, std::uint8_t counter, std::uint32_t code) noexcept {
  std::uint8_t* d = begin_reply(response, counter, sdo_info::kErrorRequest, 0, 4);
  if (d == nullptr) return {};
  store_le32(d, code);
  return {kPrefixSize + 4, 0};
}

SdoInformationReply mailbox_error(ByteSpan response, std::uint16_t detail) noexcept {
  return {mbx::encode_error_reply(response, 0, detail).value_or(0), 0};
}

SdoInformationReply od_list(ConstByteSpan request, const ObjectDictionary& od, ByteSpan response, std::uint8_t counter,
                            std::uint16_t fragment) noexcept {
  if (request.size() < 2) return mailbox_error(response, mbx::error_code::kSizeTooShort);
  const std::uint16_t list = load_le16(request.data());
  if (list > kListTypes) return error_request(response, counter, abort_code::kUnsupportedAccess);
  const std::size_t count = list == kLengths ? kListTypes : list_length(od, list);
  const std::size_t total = 2 + 2 * count;  // list type, then the words
  if (response.size() < kPrefixSize + 2) return {};
  const std::size_t per_fragment = (response.size() - kPrefixSize) & ~std::size_t{1};
  const std::size_t fragments = (total + per_fragment - 1) / per_fragment;
  if (fragment >= fragments) return {};
  const std::size_t first = fragment * per_fragment;
  const std::size_t end = std::min(total, first + per_fragment);
  const auto left = static_cast<std::uint16_t>(fragments - 1 - fragment);
  std::uint8_t* d = begin_reply(response, counter, sdo_info::kGetOdListResponse, left, end - first);
  if (d == nullptr) return {};
  // Word w of the whole answer (0: the list type) goes to d when first <= 2w < end.
  std::size_t word = 0;
  const auto put = [&](std::uint16_t value) {
    const std::size_t at = 2 * word++;
    if (at >= first && at < end) store_le16(d + (at - first), value);
  };
  put(list);
  if (list == kLengths) {
    for (std::uint16_t l = kAll; l <= kListTypes; ++l) put(list_length(od, l));
  } else {
    for_each_index(od, list, put);
  }
  return {kPrefixSize + (end - first), left};
}

// "RxPDO mapping: entries" -> "RxPDO mapping" for an object with subindexes.
std::size_t object_name_length(const ObjectEntry& e, bool has_subindexes) noexcept {
  const std::size_t n = std::strlen(e.name);
  if (!has_subindexes) return n;
  const char* colon = std::strchr(e.name, ':');
  return colon == nullptr ? n : static_cast<std::size_t>(colon - e.name);
}

SdoInformationReply object_description(ConstByteSpan request, const ObjectDictionary& od, ByteSpan response,
                                       std::uint8_t counter) noexcept {
  if (request.size() < 2) return mailbox_error(response, mbx::error_code::kSizeTooShort);
  const std::uint16_t index = load_le16(request.data());
  const ObjectEntry* sub0 = od.find(index, 0);
  if (sub0 == nullptr) return error_request(response, counter, abort_code::kObjectDoesNotExist);
  std::uint8_t max_sub = 0;
  std::uint16_t element_type = 0;
  bool same_type = true;
  for (const ObjectEntry& e : od.entries()) {
    if (e.index != index || e.subindex == 0) continue;
    max_sub = std::max(max_sub, e.subindex);
    if (element_type == 0) element_type = e.data_type;
    same_type = same_type && e.data_type == element_type;
  }
  std::uint8_t code = sdo_info::kObjectCodeVar;
  std::uint16_t type = sub0->data_type;
  if (max_sub > 0) {
    if (index == 0x1018) {
      code = sdo_info::kObjectCodeRecord;
      type = kDataTypeIdentity;
    } else if (in_range(index, 0x1600, 0x17FF) || in_range(index, 0x1A00, 0x1BFF)) {
      code = sdo_info::kObjectCodeRecord;
      type = kDataTypePdoMapping;
    } else {
      code = same_type ? sdo_info::kObjectCodeArray : sdo_info::kObjectCodeRecord;
      type = same_type ? element_type : 0;
    }
  }
  constexpr std::size_t kFixed = 6;  // index, data type, max subindex, object code
  if (response.size() < kPrefixSize + kFixed) return {};
  const std::size_t name = std::min(object_name_length(*sub0, max_sub > 0), response.size() - kPrefixSize - kFixed);
  std::uint8_t* d = begin_reply(response, counter, sdo_info::kGetObjectDescriptionResponse, 0, kFixed + name);
  if (d == nullptr) return {};
  store_le16(d, index);
  store_le16(d + 2, type);
  d[4] = max_sub;
  d[5] = code;
  std::memcpy(d + kFixed, sub0->name, name);
  return {kPrefixSize + kFixed + name, 0};
}

std::uint16_t access_bits(const ObjectDictionary& od, const ObjectEntry& e) noexcept {
  std::uint16_t bits = sdo_info::kAccessReadAll;
  if (e.access == Access::rw) bits = static_cast<std::uint16_t>(bits | sdo_info::kAccessWriteAll);
  if (e.access == Access::rw_preop) bits = static_cast<std::uint16_t>(bits | sdo_info::kAccessWritePreOp);
  if (rx_mappable(od, e.index, e.subindex)) bits = static_cast<std::uint16_t>(bits | sdo_info::kAccessRxPdoMappable);
  if (tx_mappable(od, e.index, e.subindex)) bits = static_cast<std::uint16_t>(bits | sdo_info::kAccessTxPdoMappable);
  return bits;
}

SdoInformationReply entry_description(ConstByteSpan request, const ObjectDictionary& od, ByteSpan response,
                                      std::uint8_t counter) noexcept {
  if (request.size() < 4) return mailbox_error(response, mbx::error_code::kSizeTooShort);
  const std::uint16_t index = load_le16(request.data());
  const std::uint8_t subindex = request[2];
  const ObjectEntry* e = od.find(index, subindex);
  if (e == nullptr) {
    return error_request(response, counter,
                         od.has_index(index) ? abort_code::kSubindexDoesNotExist : abort_code::kObjectDoesNotExist);
  }
  constexpr std::size_t kFixed = 10;  // index, subindex, value info, data type, bit length, access
  if (response.size() < kPrefixSize + kFixed) return {};
  const std::size_t name = std::min(std::strlen(e->name), response.size() - kPrefixSize - kFixed);
  std::uint8_t* d = begin_reply(response, counter, sdo_info::kGetEntryDescriptionResponse, 0, kFixed + name);
  if (d == nullptr) return {};
  store_le16(d, index);
  d[2] = subindex;
  d[3] = 0;  // value info: neither unit type nor default, minimum or maximum value follow
  store_le16(d + 4, e->data_type);
  store_le16(d + 6, static_cast<std::uint16_t>(e->size * 8U));
  store_le16(d + 8, access_bits(od, *e));
  std::memcpy(d + kFixed, e->name, name);
  return {kPrefixSize + kFixed + name, 0};
}

}  // namespace

SdoInformationReply serve_sdo_information(ConstByteSpan coe_payload, const ObjectDictionary& od, ByteSpan response,
                                          std::uint8_t counter, std::uint16_t fragment) noexcept {
  if (coe_payload.size() < kInfoHeaderSize) return mailbox_error(response, mbx::error_code::kSizeTooShort);
  const auto opcode = static_cast<std::uint8_t>(coe_payload[0] & ~sdo_info::kIncomplete);
  const ConstByteSpan request = coe_payload.subspan(kInfoHeaderSize, coe_payload.size() - kInfoHeaderSize);
  if (opcode == sdo_info::kGetOdListRequest) return od_list(request, od, response, counter, fragment);
  if (fragment != 0) return {};
  switch (opcode) {
    case sdo_info::kGetObjectDescriptionRequest: return object_description(request, od, response, counter);
    case sdo_info::kGetEntryDescriptionRequest: return entry_description(request, od, response, counter);
    default: return error_request(response, counter, abort_code::kUnknownCommand);
  }
}

}  // namespace rescue::drivers
