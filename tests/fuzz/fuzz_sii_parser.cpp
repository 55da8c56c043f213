// libFuzzer target: Sii::parse on arbitrary bytes must never read out of bounds, and whatever it
// accepts must be self-consistent (strings inside the image, PDO entries inside their tables).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "ecat/sii/sii.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue::ecat::sii;
  for (ChecksumPolicy policy : {ChecksumPolicy::require, ChecksumPolicy::ignore}) {
    auto r = Sii::parse(rescue::ConstByteSpan(data, size), policy);
    if (!r.ok()) continue;
    const Sii& s = r.value();
    if (s.end_offset > size) std::abort();
    std::size_t chars = 0;
    for (std::size_t i = 1; i <= s.string_count(); ++i) chars += s.string(static_cast<std::uint8_t>(i)).size();
    if (chars > size) std::abort();
    for (const Pdo& p : s.tx_pdos) {
      for (const PdoEntry& e : s.tx_entries_of(p)) chars += e.bit_length;
    }
    for (const Pdo& p : s.rx_pdos) {
      for (const PdoEntry& e : s.rx_entries_of(p)) chars += e.bit_length;
    }
    (void)s.name();
    (void)s.default_bits_of_sync_manager(2);
    (void)chars;
  }
  return 0;
}
