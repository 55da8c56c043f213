#include "drivers/sim/coe/object_dictionary.hpp"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <utility>

#include "core/base/endian.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "ecat/mailbox/coe.hpp"

namespace rescue::drivers {

namespace abort_code = ecat::coe::abort_code;

ObjectDictionary::ObjectDictionary(Span<const ObjectEntry> entries, ByteSpan storage, Validator validator) noexcept
    : entries_(entries), storage_(storage), validator_(validator) {
  assert(std::is_sorted(entries_.begin(), entries_.end(), [](const ObjectEntry& a, const ObjectEntry& b) {
    return a.index != b.index ? a.index < b.index : a.subindex < b.subindex;
  }));
  std::memset(storage_.data(), 0, storage_.size());
}

const ObjectEntry* ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex) const noexcept {
  // The table is sorted by (index, subindex) (entries_are_sorted, checked by the constructor).
  const auto* it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(index, subindex),
                                    [](const ObjectEntry& e, const std::pair<std::uint16_t, std::uint8_t>& key) {
                                      return e.index != key.first ? e.index < key.first : e.subindex < key.second;
                                    });
  return it != entries_.end() && it->index == index && it->subindex == subindex ? it : nullptr;
}

bool ObjectDictionary::has_index(std::uint16_t index) const noexcept {
  // Every index starts at subindex 0 (entries_are_sorted).
  return find(index, 0) != nullptr;
}

const ObjectEntry& ObjectDictionary::entry(std::uint16_t index, std::uint8_t subindex) const noexcept {
  const ObjectEntry* e = find(index, subindex);
  assert(e != nullptr);
  return *e;
}

ObjectRead ObjectDictionary::read(std::uint16_t index, std::uint8_t subindex) const noexcept {
  const ObjectEntry* e = find(index, subindex);
  if (e == nullptr) return {has_index(index) ? abort_code::kSubindexDoesNotExist : abort_code::kObjectDoesNotExist, {}};
  std::size_t length = e->size;
  if (e->data_type == data_type::kVisibleString) {
    // A visible string is as long as its text; the rest of its capacity is NUL.
    length = 0;
    while (length < e->size && storage_[e->offset + length] != 0) ++length;
  }
  return {0, ConstByteSpan(storage_.data() + e->offset, length)};
}

std::uint32_t ObjectDictionary::write(std::uint16_t index, std::uint8_t subindex, ConstByteSpan value,
                                      ecat::reg::AlState state) noexcept {
  const ObjectEntry* e = find(index, subindex);
  if (e == nullptr) return has_index(index) ? abort_code::kSubindexDoesNotExist : abort_code::kObjectDoesNotExist;
  if (e->access == Access::ro) return abort_code::kReadOnly;
  if (e->access == Access::rw_preop && state != ecat::reg::AlState::pre_op) return abort_code::kCannotTransferInState;
  const bool text = e->data_type == data_type::kVisibleString;
  if (text ? value.size() > e->size : value.size() != e->size) return abort_code::kLengthMismatch;
  if (validator_ != nullptr) {
    const std::uint32_t refused = validator_(*this, *e, value);
    if (refused != 0) return refused;
  }
  std::memset(storage_.data() + e->offset, 0, e->size);
  std::memcpy(storage_.data() + e->offset, value.data(), value.size());
  return 0;
}

void ObjectDictionary::set_string(std::uint16_t index, std::uint8_t subindex, const char* text) noexcept {
  const ObjectEntry& e = entry(index, subindex);
  std::memset(storage_.data() + e.offset, 0, e.size);
  const std::size_t length = std::strlen(text);
  std::memcpy(storage_.data() + e.offset, text, length < e.size ? length : e.size);
}

}  // namespace rescue::drivers
