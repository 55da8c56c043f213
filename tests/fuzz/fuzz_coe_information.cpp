// libFuzzer target: the master's CoE SDO Information decoders (ecat/mailbox/coe_information.hpp) on
// arbitrary mailbox messages must never read out of bounds: a fragment's data is what follows its
// 4-byte header, a description's name what follows its fixed part, an OD list's indexes its even
// rest; every index of a decoded list is inside it. Seeds (seeds-fuzz_coe_information/): whole
// mailbox messages of an OD list response, its first fragment, an object and an entry description,
// an SDO Info Error and a Get OD List request.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/coe_information.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue::ecat;
  namespace info = coe::info;
  const rescue::ConstByteSpan bytes(data, size);
  // The body decoders on the raw bytes too, whatever the structure.
  (void)info::decode_object_description(bytes);
  (void)info::decode_entry_description(bytes);
  (void)info::decode_od_list(bytes);
  const auto c = coe::decode(bytes);
  if (!c.ok() || c.value().service != coe::Service::sdo_information) return 0;
  const auto f = info::decode_fragment(c.value().payload);
  if (!f.ok()) return 0;
  if (f.value().data.size() + info::kInfoHeaderSize != c.value().payload.size()) std::abort();
  const rescue::ConstByteSpan body = f.value().data;
  if (const auto o = info::decode_object_description(body); o.ok()) {
    if (o.value().name.size() + info::kObjectDescriptionHead != body.size()) std::abort();
    (void)info::object_code_name(o.value().object_code);
  }
  if (const auto e = info::decode_entry_description(body); e.ok()) {
    if (e.value().name.size() + info::kEntryDescriptionHead != body.size()) std::abort();
    char access[7];
    info::access_text(e.value().access, access);
    (void)info::data_type_name(e.value().data_type);
  }
  if (const auto l = info::decode_od_list(body); l.ok()) {
    if (2 + 2 * l.value().count != body.size()) std::abort();
    std::uint32_t sum = 0;
    for (std::size_t i = 0; i < l.value().count; ++i) sum += l.value().index(i);
    (void)sum;
  }
  return 0;
}
