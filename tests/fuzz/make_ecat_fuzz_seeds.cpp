// Writes the seed corpora of fuzz_frame_decoder, fuzz_capture_reader, fuzz_captured_link and
// fuzz_sii_cache_file (cache files of 0, 1 and 2 minimal SII images, their CRCs right) at build time:
//   make_ecat_fuzz_seeds SEED_ROOT [SHARED_DIR]
// into SEED_ROOT/seeds-fuzz_frame_decoder, .../seeds-fuzz_capture_reader and
// .../seeds-fuzz_captured_link (toolchain/check.sh hands these directories to the fuzzers). Seeds are
// built with our own codec: every command and address form, VLAN, Ethernet padding, zero padding
// after the last datagram (a 1-byte BWR in a frame whose header says 14), FCS, 124 datagrams, the
// largest frame, the robot's cyclic frame, captures in every pcap/pcapng flavour the reader knows,
// Linux cooked (SLL, SLL2) packets and captures. When SHARED_DIR holds the
// real captures, their first frames and a short valid head of each file are added too; they stay
// in the build tree, never in the repository.
#include <sys/stat.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "ecat/capture/capture_reader.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/sii/sii.hpp"
#include "ecat/sii/sii_cache.hpp"
#include "tests/support/capture_bytes.hpp"

namespace {

using namespace rescue;        // NOLINT(google-build-using-namespace)
using namespace rescue::ecat;  // NOLINT(google-build-using-namespace)
using Bytes = std::vector<std::uint8_t>;

int g_written = 0;

void write_seed(const std::string& dir, const std::string& name, const Bytes& bytes) {
  std::ofstream out(dir + "/" + name, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  ++g_written;
}

Bytes finish(FrameBuilder& b) {
  const ConstByteSpan f = b.finish();
  return Bytes(f.begin(), f.end());
}

std::vector<Bytes> synthetic_frames() {
  std::vector<Bytes> frames;
  for (std::uint8_t raw = 0; raw < kCommandCount; ++raw) {
    FrameBuilder b;
    b.reset(MacAddress{0x02, 0, 0, 0, 0, raw});
    (void)b.add(static_cast<Command>(raw), raw, make_address(position_adp(raw), 0x0130), 2, {}, 0, 1);
    (void)b.add(static_cast<Command>(raw), raw, make_address(0x1000 + raw, 0x0910), 8, {}, 0, 2);
    frames.push_back(finish(b));
  }
  FrameBuilder cyclic;  // the robot's frame: DC reference time, then one LRW per branch
  (void)cyclic.add(Command::FRMW, 1, make_address(0x1000, 0x0910), 8);
  for (std::uint32_t branch = 0; branch < 4; ++branch) (void)cyclic.add(Command::LRW, 2, branch * 0x100U, 105);
  frames.push_back(finish(cyclic));
  FrameBuilder many;
  for (int i = 0; i < 124; ++i) (void)many.add(Command::NOP, 0, 0, 0);
  frames.push_back(finish(many));
  FrameBuilder largest;
  (void)largest.add(Command::LRD, 0, 0, static_cast<std::uint16_t>(kMaxDatagramDataLength));
  frames.push_back(finish(largest));
  FrameBuilder empty;
  (void)empty.add(Command::BRD, 0, 0, 0);
  Bytes unpadded = finish(empty);
  unpadded.resize(28);
  frames.push_back(unpadded);
  Bytes tagged = frames[4];
  tagged.insert(tagged.begin() + 12, {0x81, 0x00, 0x00, 0x05});
  frames.push_back(tagged);
  Bytes with_fcs = frames.back();
  with_fcs.insert(with_fcs.end(), {0x12, 0x34, 0x56, 0x78});
  frames.push_back(with_fcs);
  FrameBuilder odd;  // a 1-byte BWR padded to an even EtherCAT length, as real masters send it
  (void)odd.add(Command::BWR, 5, make_address(0, 0x0120), 1);
  Bytes padded = finish(odd);
  store_le16(padded.data() + 14, static_cast<std::uint16_t>(0x1000 | 14));
  frames.push_back(padded);
  return frames;
}

// A Linux cooked packet (SLL when !v2, SLL2 when v2) around an Ethernet frame's payload.
Bytes cooked(bool v2, const Bytes& ethernet) {
  Bytes p = v2 ? Bytes{0x88, 0xA4, 0, 0, 0, 0, 0, 2, 0, 1, 4, 6, 2, 0, 0, 0, 0, 1, 0, 0}
               : Bytes{0, 4, 0, 1, 0, 6, 2, 0, 0, 0, 0, 1, 0, 0, 0x88, 0xA4};
  if (ethernet.size() > kEthernetHeaderSize) p.insert(p.end(), ethernet.begin() + kEthernetHeaderSize, ethernet.end());
  return p;
}

Bytes read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

// A minimal SII image that parses with its CRC: the header (identity with `serial`) and the end marker.
SiiImage minimal_sii(std::uint32_t serial) {
  SiiImage image;
  store_le32(image.bytes.data() + 2 * sii::kVendorId, 0x00000ABC);
  store_le32(image.bytes.data() + 2 * sii::kProductCode, 0x4A443432);
  store_le32(image.bytes.data() + 2 * sii::kSerial, serial);
  store_le16(image.bytes.data() + 2 * sii::kEepromSize, 0x000F);
  store_le16(image.bytes.data() + 2 * sii::kVersion, 1);
  image.bytes[2 * sii::kConfigChecksum] = sii::config_area_crc(image.bytes.data());
  store_le16(image.bytes.data() + kSiiHeaderBytes, 0xFFFF);
  image.size = static_cast<std::uint16_t>(kSiiHeaderBytes + 2);
  image.complete = true;
  return image;
}

void write_sii_cache_seeds(const std::string& dir) {
  SiiCache cache;
  for (std::uint32_t images = 0; images <= 2; ++images) {
    if (images > 0) (void)cache.remember(minimal_sii(0x52460000U + images));
    Bytes file(kSiiCacheFileMax);
    const Result<std::size_t> n = cache.encode(ByteSpan(file.data(), file.size()));
    if (!n.ok()) continue;
    file.resize(n.value());
    write_seed(dir, "cache-" + std::to_string(images), file);
  }
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: make_ecat_fuzz_seeds SEED_ROOT [SHARED_DIR]\n");
    return 2;
  }
  const std::string root = argv[1];
  const std::string frames_dir = root + "/seeds-fuzz_frame_decoder";
  const std::string captures_dir = root + "/seeds-fuzz_capture_reader";
  const std::string links_dir = root + "/seeds-fuzz_captured_link";
  ::mkdir(root.c_str(), 0755);
  ::mkdir(frames_dir.c_str(), 0755);
  ::mkdir(captures_dir.c_str(), 0755);
  ::mkdir(links_dir.c_str(), 0755);
  const std::string cache_dir = root + "/seeds-fuzz_sii_cache_file";
  ::mkdir(cache_dir.c_str(), 0755);
  write_sii_cache_seeds(cache_dir);

  const std::vector<Bytes> frames = synthetic_frames();
  for (std::size_t i = 0; i < frames.size(); ++i) write_seed(frames_dir, "synthetic-" + std::to_string(i), frames[i]);
  // fuzz_captured_link: first byte picks the link type (0 Ethernet, 1 SLL, 2 SLL2, 3 unsupported).
  for (std::size_t i = 0; i < frames.size(); i += 3) {
    for (std::uint8_t link = 0; link < 4; ++link) {
      Bytes seed{link};
      const Bytes packet = link == 1 || link == 2 ? cooked(link == 2, frames[i]) : frames[i];
      seed.insert(seed.end(), packet.begin(), packet.end());
      write_seed(links_dir, "link" + std::to_string(link) + "-" + std::to_string(i), seed);
    }
  }
  for (const bool v2 : {false, true}) {  // cooked captures for the reader
    test::PcapngBuilder ng(false);
    ng.interface(v2 ? 276 : 113).packet(0, 1, cooked(v2, frames[0])).packet(0, 2, cooked(v2, frames.back()));
    write_seed(captures_dir, v2 ? "sll2.pcapng" : "sll.pcapng", ng.bytes());
    test::PcapBuilder pcap(false, false, v2 ? 276 : 113);
    pcap.record(1, 2, cooked(v2, frames[1]));
    write_seed(captures_dir, v2 ? "sll2.pcap" : "sll.pcap", pcap.bytes());
  }

  // Captures: our writer, and hand-built flavours of both formats.
  {
    CaptureWriter w;
    const std::string path = captures_dir + "/writer.pcapng";
    if (w.open(path.c_str()).ok()) {
      for (std::size_t i = 0; i < 6; ++i) {
        w.record(ConstByteSpan(frames[i].data(), frames[i].size()), static_cast<hal::Nanoseconds>(i) * 1000,
                 i % 2 == 0 ? FrameDirection::outbound : FrameDirection::inbound);
      }
      ++g_written;
    }
  }
  for (const bool big : {false, true}) {
    for (const bool nanos : {false, true}) {
      test::PcapBuilder pcap(big, nanos);
      pcap.record(1, 2, frames[0]).record(3, 4, frames[15]);
      write_seed(captures_dir, std::string("pcap-") + (big ? "be" : "le") + (nanos ? "-ns" : "-us"), pcap.bytes());
    }
    test::PcapngBuilder ng(big);
    ng.interface(capture::kLinkTypeEthernet, 0, std::uint8_t{0x80 | 20}, std::int64_t{-5}, std::uint8_t{4})
        .interface(101)
        .packet(0, 7, frames[1], 2U)
        .simple_packet(frames[2])
        .obsolete_packet(1, 8, frames[3])
        .block(5, Bytes(16, 0));
    ng.section(!big).interface().packet(0, 9, frames[4], 1U);
    write_seed(captures_dir, std::string("pcapng-") + (big ? "be" : "le"), ng.bytes());
  }

  // Real frames and short valid heads of the real captures, when they are there.
  if (argc >= 3) {
    for (const char* name : {"twincat-run-ek1100-el1004.pcapng", "soem-single-lan9252.pcapng",
                             "soem-sdinfo-akd.pcapng", "replay-dc.pcapng"}) {
      const Bytes file = read_file(std::string(argv[2]) + "/vectors/captures/" + name);
      auto reader = CaptureReader::open(ConstByteSpan(file.data(), file.size()));
      if (!reader.ok()) continue;
      CapturedFrame f;
      std::size_t head_end = 0;
      for (int i = 0; i < 40 && reader.value().next(f).value_or(false); ++i) {
        write_seed(frames_dir, std::string(name) + "-" + std::to_string(f.number), Bytes(f.bytes.begin(), f.bytes.end()));
        if (reader.value().offset() <= 4096) head_end = reader.value().offset();
      }
      if (head_end > 0) write_seed(captures_dir, std::string("head-") + name, Bytes(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(head_end)));
    }
  }
  std::printf("make_ecat_fuzz_seeds: %d seeds in %s\n", g_written, root.c_str());
  return 0;
}
