#include "drivers/object_dictionary.hpp"

#include <algorithm>
#include <cassert>
#include <cstring>

#include "core/endian.hpp"
#include "drivers/joint_drive_pdo.hpp"
#include "ecat/coe.hpp"

namespace rescue::drivers {

namespace abort_code = ecat::coe::abort_code;

ObjectDictionary::ObjectDictionary(Span<const ObjectEntry> entries, ByteSpan storage, Validator validator) noexcept
    : entries_(entries), storage_(storage), validator_(validator) {
  std::memset(storage_.data(), 0, storage_.size());
}

const ObjectEntry* ObjectDictionary::find(std::uint16_t index, std::uint8_t subindex) const noexcept {
  const auto* it = std::find_if(entries_.begin(), entries_.end(),
                                [&](const ObjectEntry& e) { return e.index == index && e.subindex == subindex; });
  return it == entries_.end() ? nullptr : it;
}

bool ObjectDictionary::has_index(std::uint16_t index) const noexcept {
  return std::any_of(entries_.begin(), entries_.end(), [&](const ObjectEntry& e) { return e.index == index; });
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

std::uint32_t ObjectDictionary::get_u32(std::uint16_t index, std::uint8_t subindex) const noexcept {
  const ObjectEntry& e = entry(index, subindex);
  assert(e.size <= 4);
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < e.size; ++i) v |= static_cast<std::uint32_t>(storage_[e.offset + i]) << (8U * i);
  return v;
}

std::int32_t ObjectDictionary::get_i32(std::uint16_t index, std::uint8_t subindex) const noexcept {
  const ObjectEntry& e = entry(index, subindex);
  const std::uint32_t raw = get_u32(index, subindex);
  switch (e.size) {
    case 1: return static_cast<std::int8_t>(raw);
    case 2: return static_cast<std::int16_t>(raw);
    default: return static_cast<std::int32_t>(raw);
  }
}

void ObjectDictionary::set(std::uint16_t index, std::uint8_t subindex, std::uint32_t value) noexcept {
  const ObjectEntry& e = entry(index, subindex);
  assert(e.size <= 4);
  for (std::size_t i = 0; i < e.size; ++i) storage_[e.offset + i] = static_cast<std::uint8_t>(value >> (8U * i));
}

void ObjectDictionary::set_string(std::uint16_t index, std::uint8_t subindex, const char* text) noexcept {
  const ObjectEntry& e = entry(index, subindex);
  std::memset(storage_.data() + e.offset, 0, e.size);
  const std::size_t length = std::strlen(text);
  std::memcpy(storage_.data() + e.offset, text, length < e.size ? length : e.size);
}

}  // namespace rescue::drivers
