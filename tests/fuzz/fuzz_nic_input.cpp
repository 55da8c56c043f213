// Fuzzes what the NIC layer does with untrusted input: the EtherType filter and the ESC's source
// marking on arbitrary frames (as they come off the wire), and the --nic option text.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/app/config/nic_option.hpp"
#include "core/app/sim/frame_server.hpp"
#include "hal/net/raw_socket_nic.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> frame(data, data + size);  // exact size: reads past it are caught
  (void)rescue::hal::is_ethercat_frame(rescue::ConstByteSpan(frame.data(), frame.size()));
  rescue::app::mark_processed_by_esc(rescue::ByteSpan(frame.data(), frame.size()));
  // Only SOURCE_MAC[1] may change, and only in a frame long enough to have an Ethernet header.
  const bool marked = size >= 14;
  for (std::size_t i = 0; i < size; ++i) {
    const std::uint8_t expected = (marked && i == 6) ? static_cast<std::uint8_t>(data[i] | 0x02) : data[i];
    if (frame[i] != expected) __builtin_trap();
  }

  std::vector<char> text(data, data + size);
  text.push_back('\0');
  const auto choice = rescue::app::parse_nic_option(text.data());
  if (choice.ok() && choice.value().kind == rescue::app::NicKind::raw) {
    const char* name = choice.value().interface_name.data();
    const std::size_t length = strnlen(name, choice.value().interface_name.size());
    if (length == 0 || length > rescue::hal::kMaxInterfaceNameLength) __builtin_trap();
  }
  return 0;
}
