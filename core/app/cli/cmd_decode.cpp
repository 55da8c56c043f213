// rescue-motion decode FILE: one line per EtherCAT datagram of a pcap/pcapng capture (design brief
// section 7), e.g. `3022 FRMW 230 0x1000:0x0910 8 2`, and `3022 PAD 1` for padding after the last
// datagram. The capture is streamed, one record or block at a time, through a fixed window of
// kWindowBytes (bounded memory whatever the file's size: a 2 GiB file is not read into memory first);
// it is opened as a regular file only (hal/files/trusted_file.hpp: no hang on a FIFO) and read with
// pread into the window, never mapped (no SIGBUS when the file is truncated meanwhile); every frame goes
// through the same decoder the master uses, behind an Ethernet or Linux cooked (SLL, SLL2) link layer.
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>

#include "core/app/cli/commands.hpp"
#include "ecat/capture/capture_reader.hpp"
#include "ecat/capture/captured_link.hpp"
#include "ecat/codec/frame.hpp"
#include "hal/files/trusted_file.hpp"

namespace rescue::app {
namespace {

// The window the capture is read through: the largest record (256 KiB) twice, and room for a pcapng
// block of up to 1 MiB (a larger one is refused: "block length", capacity_exceeded).
constexpr std::size_t kWindowBytes = std::size_t{1} << 20;
static_assert(kWindowBytes >= ecat::CaptureReader::kMinWindow, "the reader needs its largest record");

// The capture file, read with pread at the reader's offsets.
class FileSource final : public ecat::CaptureSource {
 public:
  explicit FileSource(int fd) noexcept : fd_(fd) {}
  Result<std::size_t> read_at(std::size_t offset, ByteSpan out) noexcept override {
    std::size_t done = 0;
    while (done < out.size()) {
      const ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) return make_error(Errc::io_error, "read file", static_cast<std::uint32_t>(errno));
      if (n == 0) break;  // the end of the file
      done += static_cast<std::size_t>(n);
    }
    return done;
  }

 private:
  int fd_;
};

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

int open_error(const hal::FileProblem& why) {
  char message[sizeof why.text + 16];
  (void)std::snprintf(message, sizeof message, "cannot read %s", why.c_str());
  return fail("decode", message);
}

// The reader's errors name the field, the frame being read and the byte offset in the file.
// A file truncated by someone else while it was read says so.
int capture_error(const char* path, const Error& e, bool shrank) {
  char message[320];
  (void)std::snprintf(message, sizeof message, "cannot read %s: %s: %s (frame %" PRIu32 ", byte %" PRIu32 ")%s", path,
                      e.what, to_string(e.code), e.detail0, e.detail1,
                      shrank ? "; the file shrank while it was read" : "");
  return fail("decode", message);
}

// The window: static, one decode per process.
std::array<std::uint8_t, kWindowBytes> g_window{};

int decode_main(const ParsedArgs& args) {
  const char* path = args.positional(0);
  hal::FileProblem why;
  const Result<hal::OpenFile> opened = hal::open_regular_for_read(path, why);
  if (!opened.ok()) return open_error(why);
  struct stat at_open {};
  const std::size_t size_at_open =
      ::fstat(opened.value().fd(), &at_open) == 0 ? static_cast<std::size_t>(at_open.st_size) : 0;
  FileSource source(opened.value().fd());
  // Whether the file is now shorter than when it was opened: someone truncated it meanwhile.
  const int fd = opened.value().fd();
  const auto shrank = [fd, size_at_open] {
    struct stat now {};
    return ::fstat(fd, &now) == 0 && static_cast<std::size_t>(now.st_size) < size_at_open;
  };
  auto reader = ecat::CaptureReader::open(source, ByteSpan(g_window));
  if (!reader.ok()) return capture_error(path, reader.error(), shrank());

  ecat::CapturedFrame frame;
  std::uint32_t unsupported_frames = 0;
  std::uint16_t unsupported_link_type = 0;
  for (;;) {
    const Result<bool> more = reader.value().next(frame);
    if (!more.ok()) {
      (void)std::fflush(stdout);  // the lines so far first, then the reason
      return capture_error(path, more.error(), shrank());
    }
    if (!more.value()) break;
    if (!ecat::is_supported_link_type(frame.link_type)) {
      if (unsupported_frames++ == 0) unsupported_link_type = frame.link_type;
      continue;
    }
    const auto parsed = ecat::decode_captured_frame(frame.link_type, frame.bytes);
    if (!parsed.ok()) {
      if (!is_not_ethercat(parsed.error())) print_frame_error(frame.number, parsed.error());
      continue;
    }
    for (const ecat::DatagramView d : parsed.value()) print_datagram(frame.number, d);
    if (parsed.value().header().padding != 0) {
      (void)std::printf("%" PRIu32 " PAD %u\n", frame.number, parsed.value().header().padding);
    }
  }
  if (std::fflush(stdout) != 0 || std::ferror(stdout) != 0) return fail("decode", "cannot write the listing");
  if (shrank()) return fail("decode", "the file shrank while it was read: the listing stops where its bytes did");
  if (unsupported_frames != 0) {
    char message[256];
    (void)std::snprintf(message, sizeof message,
                        "%" PRIu32 " frame(s) not decoded: link type %u is not supported (1 Ethernet, 113 Linux cooked SLL, "
                        "276 Linux cooked SLL2)",
                        unsupported_frames, unsupported_link_type);
    return fail("decode", message);
  }
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
    "Zero bytes after a frame's last datagram inside the EtherCAT length (a master padding an odd\n"
    "length to an even one) print 'frame PAD bytes'.\n"
    "Link types: Ethernet (1), Linux cooked SLL (113, tcpdump -i any) and SLL2 (276, tshark -i any).\n"
    "Frames that are not EtherCAT are skipped; malformed ones print 'frame ERROR reason'.\n"
    "Only regular files are read (a FIFO or device is refused at once).\n"
    "Exit status 0 when the whole file was read and decoded; 1, with the reason on stderr, when it\n"
    "could not be or when frames of another link type were left out (the listing still covers the rest).",
    Span<const OptionSpec>(), 1, 1, decode_main};

}  // namespace rescue::app
