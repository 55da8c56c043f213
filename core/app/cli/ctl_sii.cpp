#include "core/app/cli/ctl_sii.hpp"

#include <array>
#include <cstdio>
#include <cstring>

#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "core/app/cli/ctl_target.hpp"
#include "core/app/cli/esi_xml.hpp"
#include "core/robot/robot.hpp"
#include "ecat/sii/sii.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

struct Image {
  std::array<std::uint8_t, protocol::kSiiImageBytes> bytes{};
  std::size_t size{0};
  std::uint8_t flags{0};
};

struct SlaveImage {
  std::size_t position{0};
  const char* name{""};
  Image image;
};

// ctl xml's description: a drive's is about 6 KB; the most the SII parser holds (64 PDOs and 256
// entries each way) about 100 KB.
constexpr std::size_t kXmlCapacity = std::size_t{1} << 17U;

// Asks for the chunks from offset 0 until the image is whole. Errors: the exchange's (unreachable),
// mismatch (an answer of another type, or one that does not continue the image where it stands).
Result<Image> read_image(CtlPeer& peer, std::uint8_t slave) noexcept {
  Image image;
  Message request;
  request.header.type = MessageType::get_sii;
  request.sii_request.slave = slave;
  for (std::size_t chunks = 0; chunks <= protocol::kSiiImageBytes / protocol::kSiiChunkBytes; ++chunks) {
    request.sii_request.offset = static_cast<std::uint16_t>(image.size);
    const Result<Message> answer = peer.exchange(request);
    if (!answer.ok()) return answer.error();
    const protocol::SiiPayload& c = answer.value().sii;
    // The codec checked offset + length <= size <= kSiiImageBytes; the image must not change between chunks.
    if (answer.value().header.type != MessageType::sii || c.slave != slave || c.offset != image.size ||
        (chunks > 0 && (c.flags != image.flags))) {
      return make_error(Errc::mismatch, "not the next chunk of the image asked for");
    }
    image.flags = c.flags;
    std::memcpy(image.bytes.data() + c.offset, c.bytes.data(), c.length);
    image.size = c.offset + c.length;
    if (image.size >= c.size || c.length == 0) return image;
  }
  return make_error(Errc::mismatch, "the image did not end");
}

void print_hex_dump(const Image& image) noexcept {
  for (std::size_t at = 0; at < image.size; at += 16) {
    (void)std::printf("%04zx:", at);
    char text[17] = {};
    for (std::size_t i = 0; i < 16; ++i) {
      if (at + i < image.size) {
        const std::uint8_t b = image.bytes[at + i];
        (void)std::printf(" %02x", b);
        text[i] = b >= 0x20 && b <= 0x7E ? static_cast<char>(b) : '.';  // nothing of the robot's reaches the terminal raw
      } else {
        (void)std::printf("   ");
        text[i] = ' ';
      }
    }
    (void)std::printf("  |%s|\n", text);
  }
}

// A refusal of `verb` for slave `name` (text: one line; --json: the envelope with the reason).
int refuse_slave(const char* verb, const char* name, std::size_t position, const char* reason) noexcept {
  if (!ctl_output().json) {
    (void)std::printf("%s: %s: %s\n", verb, name, reason);
    return static_cast<int>(CtlExit::refused);
  }
  begin_json(false);
  (void)std::printf(R"(,"slave":"%s","position":%zu,"reason":)", name, position);
  print_json_string(reason);
  end_json();
  return static_cast<int>(CtlExit::refused);
}

// The slave `verb`'s first argument names and the image the master read of it, into `out`;
// returns 0, or the exit status of what went wrong (printed).
int fetch_image(const char* verb, const ParsedArgs& args, CtlPeer& peer, SlaveImage& out) noexcept {
  out.position = planned_slave_named(args.positional(1));
  if (out.position >= kSlaveCount) {
    char text[160];
    (void)std::snprintf(text, sizeof text, "%s SLAVE: '%.40s' is not a slave; a slave's name (ctl slaves) or a position 0..%zu",
                        verb, args.positional(1), kSlaveCount - 1);
    return ctl_error(CtlExit::usage, text);
  }
  const Result<Image> read = read_image(peer, static_cast<std::uint8_t>(out.position));
  if (!read.ok()) {
    if (read.error().code == Errc::mismatch) {
      char text[96];
      (void)std::snprintf(text, sizeof text, "%s: an answer that is not the image's next chunk", verb);
      return ctl_error(CtlExit::bad_answer, text);
    }
    const Result<CtlTarget> target = peer.target();
    if (!target.ok()) return ctl_error(exit_of(target.error().code), target.error().what);
    return ctl_unreachable(read.error(), target.value());
  }
  out.image = read.value();
  out.name = planned_slave_name(out.position);
  if ((out.image.flags & protocol::kSiiRead) == 0) {
    return refuse_slave(verb, out.name, out.position, "the master has no SII image of it (not identified at bring-up)");
  }
  return 0;
}

}  // namespace

int ctl_sii_read(const ParsedArgs& args, CtlPeer& peer) noexcept {
  const bool json = ctl_output().json;
  const bool raw = args.has("raw");
  if (raw && json) return ctl_error(CtlExit::usage, "sii_read: --raw and --json exclude each other");
  static SlaveImage slave;  // 1 KiB: not on the stack
  const int fetched = fetch_image("sii_read", args, peer, slave);
  if (fetched != 0) return fetched;
  const Image& image = slave.image;
  const std::size_t position = slave.position;
  const char* name = slave.name;
  const bool cached = (image.flags & protocol::kSiiFromCache) != 0;
  const bool strings_skipped = (image.flags & protocol::kSiiStringsSkipped) != 0;
  if (raw) {
    return std::fwrite(image.bytes.data(), 1, image.size, stdout) == image.size ? 0 : static_cast<int>(CtlExit::local);
  }
  if (json) {
    begin_json(true);
    (void)std::printf(R"(,"slave":"%s","position":%zu,"size":%zu,"from_cache":%s,"strings_skipped":%s,"bytes":")", name,
                      position, image.size, cached ? "true" : "false", strings_skipped ? "true" : "false");
    for (std::size_t i = 0; i < image.size; ++i) (void)std::printf("%02x", image.bytes[i]);
    (void)std::printf("\"");
    end_json();
    return 0;
  }
  (void)std::printf("%s (position %zu): %zu bytes of SII as the master read them at bring-up%s%s\n", name, position,
                    image.size, cached ? " (after the identity: from the SII cache)" : "",
                    strings_skipped ? "; Strings the master skipped read 0" : "");
  print_hex_dump(image);
  return 0;
}

int ctl_xml(const ParsedArgs& args, CtlPeer& peer) noexcept {
  static SlaveImage slave;  // the parsed SII keeps a view of it
  const int fetched = fetch_image("xml", args, peer, slave);
  if (fetched != 0) return fetched;
  const Result<ecat::sii::Sii> sii = ecat::sii::Sii::parse(ConstByteSpan(slave.image.bytes.data(), slave.image.size),
                                                           ecat::sii::ChecksumPolicy::ignore);
  if (!sii.ok()) {
    char reason[160];
    (void)std::snprintf(reason, sizeof reason, "its SII does not parse: %s (category %u, byte %u)", sii.error().what,
                        static_cast<unsigned>(sii.error().detail0), static_cast<unsigned>(sii.error().detail1));
    return refuse_slave("xml", slave.name, slave.position, reason);
  }
  static std::array<char, kXmlCapacity> xml;
  EsiSource source;
  source.slave_name = slave.name;
  source.position = slave.position;
  source.strings_skipped = (slave.image.flags & protocol::kSiiStringsSkipped) != 0;
  if (write_esi_xml(sii.value(), source, Span<char>(xml)) == 0) {
    return ctl_error(CtlExit::local, "xml: the description does not fit ctl's buffer");
  }
  if (!ctl_output().json) {
    (void)std::fputs(xml.data(), stdout);
    return 0;
  }
  begin_json(true);
  (void)std::printf(R"(,"slave":"%s","position":%zu,"strings_skipped":%s,"xml":)", slave.name, slave.position,
                    source.strings_skipped ? "true" : "false");
  print_json_string(xml.data());
  end_json();
  return 0;
}

}  // namespace rescue::app
