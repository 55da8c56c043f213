// The CoE decoder on the mailbox traffic SOEM exchanged with a real Kollmorgen AKD
// (../shared/vectors/captures/soem-sdinfo-akd.pcapng): every SDO request SOEM wrote into SM0
// (FPWR 0x1800) and every response it read from SM1 (FPRD 0x1C00, working counter 1) decodes,
// each response answers its request, and each decoded field matches what Wireshark's dissector
// says (tshark, when installed). Our encoder rebuilds every request byte for byte.
// The capture is read with the project's own reader (ecat/capture/capture_reader.hpp).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "ecat/mailbox/coe.hpp"
#include "ecat/capture/capture_reader.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/read_frames.hpp"

namespace rescue::ecat::coe {
namespace {

const std::string kCapture = std::string(RESCUE_SHARED_DIR) + "/vectors/captures/soem-sdinfo-akd.pcapng";

struct MailboxFrame {
  std::size_t number;  // 1-based, as Wireshark numbers frames
  bool request;        // written to SM0 (else read from SM1)
  std::vector<std::uint8_t> mailbox;
};

std::vector<std::uint8_t> read_file(const std::string& path) {
  std::vector<std::uint8_t> file;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return file;
  std::uint8_t chunk[4096];
  std::size_t n = 0;
  while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0) file.insert(file.end(), chunk, chunk + n);
  std::fclose(f);
  return file;
}

std::vector<MailboxFrame> mailbox_frames() {
  std::vector<MailboxFrame> out;
  const std::vector<std::uint8_t> file = read_file(kCapture);
  if (file.empty()) return out;
  for (const CapturedFrame& captured : test::read_all_frames(file)) {
    auto frame = FrameView::parse(captured.bytes);
    if (!frame.ok()) continue;
    for (DatagramView d : frame.value()) {
      const bool req = d.command() == Command::FPWR && d.ado() == 0x1800 && d.wkc() == 0;
      const bool resp = d.command() == Command::FPRD && d.ado() == 0x1C00 && d.wkc() == 1;
      if (!req && !resp) continue;
      const auto data = d.data();
      // An empty mailbox reads as zeros: skip those polls.
      if (resp && (data.size() < 6 || (data[0] == 0 && data[1] == 0))) continue;
      out.push_back(MailboxFrame{captured.number, req, std::vector<std::uint8_t>(data.begin(), data.end())});
    }
  }
  return out;
}

// frame number -> "index,subindex" as tshark decodes it.
std::map<std::size_t, std::string> tshark_index_subindex() {
  std::map<std::size_t, std::string> out;
  const std::string cmd = "tshark -r '" + kCapture +
                          "' -Y 'ecat_mailbox.coe' -T fields -E separator=, -e frame.number "
                          "-e ecat_mailbox.coe.sdoidx -e ecat_mailbox.coe.sdosub 2>/dev/null";
  std::FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return out;
  char line[256];
  while (std::fgets(line, sizeof line, p) != nullptr) {
    std::string s(line);
    while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
    const auto comma = s.find(',');
    if (comma == std::string::npos) continue;
    out[std::stoul(s.substr(0, comma))] = s.substr(comma + 1);
  }
  pclose(p);
  return out;
}

std::string hex_pair(std::uint16_t index, std::uint8_t sub) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "0x%04x,0x%02x", index, sub);
  return buf;
}

TEST(CoeDecoderOnAkdCapture, EveryRequestAndResponseDecodesAndPairsUp) {
  const auto frames = mailbox_frames();
  if (frames.empty()) GTEST_SKIP() << "needs " << kCapture << " (shared vectors absent)";
  std::size_t requests = 0;
  std::size_t responses = 0;
  Sdo last_request{};
  for (const MailboxFrame& f : frames) {
    auto m = decode(ConstByteSpan(f.mailbox.data(), f.mailbox.size()));
    ASSERT_TRUE(m.ok()) << "frame " << f.number << ": " << m.error().what;
    const Message& msg = m.value();
    if (f.request) {
      ++requests;
      EXPECT_EQ(msg.service, Service::sdo_request) << f.number;
      EXPECT_EQ(msg.sdo.kind, SdoKind::upload_initiate_request) << f.number;
      last_request = msg.sdo;
      // Our encoder writes the same bytes SOEM wrote.
      std::array<std::uint8_t, 64> mine{};
      auto n = encode(ByteSpan(mine), msg.mailbox, upload_request(msg.sdo.index, msg.sdo.subindex));
      ASSERT_TRUE(n.ok());
      EXPECT_TRUE(std::equal(mine.begin(), mine.begin() + static_cast<long>(n.value()), f.mailbox.begin())) << f.number;
    } else {
      ++responses;
      EXPECT_EQ(msg.service, Service::sdo_response) << f.number;
      EXPECT_EQ(msg.sdo.kind, SdoKind::upload_initiate_response) << f.number;
      EXPECT_TRUE(msg.sdo.expedited);
      EXPECT_EQ(msg.sdo.index, last_request.index) << f.number;
      EXPECT_EQ(msg.sdo.subindex, last_request.subindex) << f.number;
      EXPECT_EQ(msg.sdo.data.size(), msg.sdo.size);
    }
  }
  EXPECT_EQ(requests, 35u);
  EXPECT_EQ(responses, 35u);
  // The first exchange: 0x1C00:00 (number of SyncManager types) is 4.
  auto first = decode(ConstByteSpan(frames[1].mailbox.data(), frames[1].mailbox.size()));
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first.value().sdo.index, 0x1C00);
  ASSERT_EQ(first.value().sdo.data.size(), 1u);
  EXPECT_EQ(first.value().sdo.data[0], 4);
  EXPECT_EQ(first.value().mailbox.counter, 1);
}

TEST(CoeDecoderOnAkdCapture, FieldsMatchWiresharksDissector) {
  const auto frames = mailbox_frames();
  if (frames.empty()) GTEST_SKIP() << "needs " << kCapture << " (shared vectors absent)";
  const auto expected = tshark_index_subindex();
  if (expected.empty()) GTEST_SKIP() << "tshark not installed (Debian package tshark)";
  std::size_t compared = 0;
  for (const MailboxFrame& f : frames) {
    auto m = decode(ConstByteSpan(f.mailbox.data(), f.mailbox.size()));
    ASSERT_TRUE(m.ok());
    const auto it = expected.find(f.number);
    ASSERT_NE(it, expected.end()) << "tshark saw no CoE in frame " << f.number;
    EXPECT_EQ(hex_pair(m.value().sdo.index, m.value().sdo.subindex), it->second) << f.number;
    ++compared;
  }
  EXPECT_EQ(compared, 70u);
}

}  // namespace
}  // namespace rescue::ecat::coe
