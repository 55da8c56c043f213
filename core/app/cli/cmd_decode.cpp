// rescue-motion decode FILE: one line per EtherCAT datagram of a pcap/pcapng capture (design brief
// section 7), e.g. `3022 FRMW 230 0x1000:0x0910 8 2`. The capture is mapped, not copied; every frame
// goes through the same decoder the master uses.
#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "core/app/cli/commands.hpp"
#include "ecat/capture/capture_reader.hpp"
#include "ecat/codec/frame.hpp"
#include "hal/files/mapped_file.hpp"

namespace rescue::app {
namespace {

void print_datagram(std::uint32_t frame, const ecat::DatagramView& d) {
  if (ecat::address_kind(d.command()) == ecat::AddressKind::logical) {
    (void)std::printf("%" PRIu32 " %s %u 0x%08" PRIx32 " %u %u\n", frame, ecat::mnemonic(d.command()), d.index(),
                      d.address(), d.length(), d.wkc());
  } else {
    (void)std::printf("%" PRIu32 " %s %u 0x%04x:0x%04x %u %u\n", frame, ecat::mnemonic(d.command()), d.index(),
                      d.adp(), d.ado(), d.length(), d.wkc());
  }
}

// `frame ERROR field: kind (datagram D, offset O)`; frame-level fields have no datagram.
void print_frame_error(std::uint32_t frame, const Error& e) {
  if (e.detail0 == ecat::kFrameLevel) {
    (void)std::printf("%" PRIu32 " ERROR %s: %s (offset %" PRIu32 ")\n", frame, e.what, to_string(e.code), e.detail1);
  } else {
    (void)std::printf("%" PRIu32 " ERROR %s: %s (datagram %" PRIu32 ", offset %" PRIu32 ")\n", frame, e.what,
                      to_string(e.code), e.detail0, e.detail1);
  }
}

bool is_not_ethercat(const Error& e) { return e.code == Errc::unsupported && std::strcmp(e.what, "not EtherCAT") == 0; }

int open_error(const char* path, const Error& e) {
  char message[256];
  if (e.code == Errc::io_error) {
    (void)std::snprintf(message, sizeof message, "cannot read %s: %s: %s", path, e.what,
                        std::strerror(static_cast<int>(e.detail0)));  // NOLINT(concurrency-mt-unsafe): the CLI reports from one thread
  } else {
    (void)std::snprintf(message, sizeof message, "cannot read %s: %s", path, e.what);
  }
  return fail("decode", message);
}

// The reader's errors name the field, the frame being read and the byte offset in the file.
int capture_error(const char* path, const Error& e) {
  char message[256];
  (void)std::snprintf(message, sizeof message, "cannot read %s: %s: %s (frame %" PRIu32 ", byte %" PRIu32 ")", path,
                      e.what, to_string(e.code), e.detail0, e.detail1);
  return fail("decode", message);
}

int decode_main(const ParsedArgs& args) {
  const char* path = args.positional(0);
  auto mapped = hal::MappedFile::open(path);
  if (!mapped.ok()) return open_error(path, mapped.error());
  auto reader = ecat::CaptureReader::open(mapped.value().bytes());
  if (!reader.ok()) return capture_error(path, reader.error());

  ecat::CapturedFrame frame;
  for (;;) {
    const Result<bool> more = reader.value().next(frame);
    if (!more.ok()) {
      (void)std::fflush(stdout);  // the lines so far first, then the reason
      return capture_error(path, more.error());
    }
    if (!more.value()) break;
    if (frame.link_type != ecat::capture::kLinkTypeEthernet) continue;
    const auto parsed = ecat::FrameView::parse(frame.bytes);
    if (!parsed.ok()) {
      if (!is_not_ethercat(parsed.error())) print_frame_error(frame.number, parsed.error());
      continue;
    }
    for (const ecat::DatagramView d : parsed.value()) print_datagram(frame.number, d);
  }
  if (std::fflush(stdout) != 0 || std::ferror(stdout) != 0) return fail("decode", "cannot write the listing");
  return 0;
}

}  // namespace

const CommandSpec kDecodeCommand{
    "decode", "decode FILE", "print every EtherCAT datagram of a pcap/pcapng capture, one line each",
    "Line format: frame command index address length wkc\n"
    "  frame   1-based frame number in the file\n"
    "  command mnemonic (NOP, APRD, ... FRMW)\n"
    "  index   datagram index, decimal\n"
    "  address 0xADP:0xADO for position/station/broadcast commands (and NOP), 0xLLLLLLLL for logical ones\n"
    "  length  data length in bytes, decimal\n"
    "  wkc     working counter, decimal\n"
    "Frames that are not EtherCAT are skipped; malformed ones print 'frame ERROR reason'.\n"
    "Exit status 0 when the whole file was read; 1, with the reason on stderr, when it could not be.",
    Span<const OptionSpec>(), 1, 1, decode_main};

}  // namespace rescue::app
