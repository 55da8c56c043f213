// CoE SDO codec: each kind of request and response survives encode -> decode with the bytes
// CiA 301 / ETG.1000.6 prescribe, abort codes travel intact, and bad SDOs are refused.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "ecat/mailbox/coe.hpp"

namespace rescue::ecat::coe {
namespace {

struct Encoded {
  std::array<std::uint8_t, 256> buf{};
  std::size_t size{0};
  ConstByteSpan bytes() const { return ConstByteSpan(buf.data(), size); }
  const std::uint8_t* sdo() const { return buf.data() + mbx::kHeaderSize + kCoeHeaderSize; }
};

Encoded encode_ok(const Sdo& sdo, std::uint8_t counter = 1) {
  Encoded e;
  mbx::Header h;
  h.counter = counter;
  auto n = encode(ByteSpan(e.buf), h, sdo);
  EXPECT_TRUE(n.ok()) << (n.ok() ? "" : n.error().what);
  e.size = n.value_or(0);
  return e;
}

Message decode_ok(const Encoded& e) {
  auto m = decode(e.bytes());
  EXPECT_TRUE(m.ok()) << (m.ok() ? "" : m.error().what);
  return m.ok() ? m.value() : Message{};
}

TEST(CoeSdo, ExpeditedUploadRequestMatchesSoemBytes) {
  // The request SOEM sends for 0x1C00:00 (captures/soem-sdinfo-akd.pcapng frame 281).
  const Encoded e = encode_ok(upload_request(0x1C00, 0));
  const std::vector<std::uint8_t> expected{0x0a, 0x00, 0x00, 0x00, 0x00, 0x13, 0x00, 0x20,
                                           0x40, 0x00, 0x1c, 0x00, 0x00, 0x00, 0x00, 0x00};
  ASSERT_EQ(e.size, expected.size());
  EXPECT_TRUE(std::equal(expected.begin(), expected.end(), e.buf.begin()));
  const Message m = decode_ok(e);
  EXPECT_EQ(m.service, Service::sdo_request);
  EXPECT_EQ(m.sdo.kind, SdoKind::upload_initiate_request);
  EXPECT_EQ(m.sdo.index, 0x1C00);
  EXPECT_EQ(m.sdo.subindex, 0);
  EXPECT_FALSE(m.sdo.complete_access);
}

TEST(CoeSdo, ExpeditedUploadResponseOfOneToFourBytes) {
  for (std::size_t n = 1; n <= 4; ++n) {
    const std::array<std::uint8_t, 4> value{0x11, 0x22, 0x33, 0x44};
    const Encoded e = encode_ok(upload_response(0x6041, 0, ConstByteSpan(value.data(), n)));
    EXPECT_EQ(e.size, 16u);
    EXPECT_EQ(e.sdo()[0], 0x43 | ((4 - n) << 2));  // scs=2, n, e=1, s=1 (0x4F for one byte)
    const Message m = decode_ok(e);
    EXPECT_EQ(m.service, Service::sdo_response);
    EXPECT_EQ(m.sdo.kind, SdoKind::upload_initiate_response);
    EXPECT_TRUE(m.sdo.expedited);
    EXPECT_TRUE(m.sdo.size_indicated);
    EXPECT_EQ(m.sdo.size, n);
    ASSERT_EQ(m.sdo.data.size(), n);
    for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(m.sdo.data[i], value[i]);
  }
}

TEST(CoeSdo, ExpeditedDownloadRequestAndItsResponse) {
  const std::array<std::uint8_t, 2> controlword{0x06, 0x00};
  const Encoded req = encode_ok(download_request(0x6040, 0, ConstByteSpan(controlword)));
  EXPECT_EQ(req.sdo()[0], 0x2B);  // ccs=1, n=2, e=1, s=1
  const Message m = decode_ok(req);
  EXPECT_EQ(m.sdo.kind, SdoKind::download_initiate_request);
  EXPECT_EQ(m.sdo.index, 0x6040);
  ASSERT_EQ(m.sdo.data.size(), 2u);
  EXPECT_EQ(m.sdo.data[0], 0x06);

  const Encoded resp = encode_ok(download_response(0x6040, 0));
  EXPECT_EQ(resp.sdo()[0], 0x60);
  const Message r = decode_ok(resp);
  EXPECT_EQ(r.service, Service::sdo_response);
  EXPECT_EQ(r.sdo.kind, SdoKind::download_initiate_response);
  EXPECT_EQ(r.sdo.index, 0x6040);
}

TEST(CoeSdo, NormalTransferCarriesCompleteSizeAndData) {
  const char name[] = "rescue joint drive";
  const ConstByteSpan text(reinterpret_cast<const std::uint8_t*>(name), sizeof name - 1);
  const Encoded e = encode_ok(upload_response(0x1008, 0, text));
  EXPECT_EQ(e.size, mbx::kHeaderSize + kSdoInitiateSize + text.size());
  EXPECT_EQ(e.sdo()[0], 0x41);  // scs=2, s=1, not expedited
  const Message m = decode_ok(e);
  EXPECT_FALSE(m.sdo.expedited);
  EXPECT_EQ(m.sdo.size, text.size());
  ASSERT_EQ(m.sdo.data.size(), text.size());
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(m.sdo.data.data()), m.sdo.data.size()), name);

  const Encoded d = encode_ok(download_request(0x1008, 0, text));
  const Message dm = decode_ok(d);
  EXPECT_EQ(dm.sdo.kind, SdoKind::download_initiate_request);
  EXPECT_FALSE(dm.sdo.expedited);
  EXPECT_EQ(dm.sdo.data.size(), text.size());
}

TEST(CoeSdo, NormalTransferPaddingPastTheCompleteSizeIsNotData) {
  Encoded e = encode_ok(upload_response(0x1008, 0, ConstByteSpan(reinterpret_cast<const std::uint8_t*>("abcdef"), 6)));
  e.buf[0] = static_cast<std::uint8_t>(e.buf[0] + 4);  // 4 pad bytes inside the mailbox length
  e.size += 4;
  const Message m = decode_ok(e);
  EXPECT_EQ(m.sdo.data.size(), 6u);
}

TEST(CoeSdo, SegmentsCarryToggleLastAndShortLengths) {
  const std::array<std::uint8_t, 3> tail{7, 8, 9};
  Sdo seg;
  seg.kind = SdoKind::upload_segment_response;
  seg.toggle = true;
  seg.last_segment = true;
  seg.data = ConstByteSpan(tail);
  const Encoded e = encode_ok(seg);
  EXPECT_EQ(e.size, mbx::kHeaderSize + kCoeHeaderSize + 1 + kMinSegmentData);  // padded to 7
  EXPECT_EQ(e.sdo()[0], 0x10 | (4 << 1) | 0x01);
  const Message m = decode_ok(e);
  EXPECT_EQ(m.sdo.kind, SdoKind::upload_segment_response);
  EXPECT_TRUE(m.sdo.toggle);
  EXPECT_TRUE(m.sdo.last_segment);
  ASSERT_EQ(m.sdo.data.size(), 3u);
  EXPECT_EQ(m.sdo.data[2], 9);

  std::vector<std::uint8_t> big(40, 0x5A);
  seg.kind = SdoKind::download_segment_request;
  seg.toggle = false;
  seg.last_segment = false;
  seg.data = ConstByteSpan(big.data(), big.size());
  const Message d = decode_ok(encode_ok(seg));
  EXPECT_EQ(d.service, Service::sdo_request);
  EXPECT_EQ(d.sdo.kind, SdoKind::download_segment_request);
  EXPECT_FALSE(d.sdo.toggle);
  EXPECT_FALSE(d.sdo.last_segment);
  EXPECT_EQ(d.sdo.data.size(), 40u);

  Sdo ask;
  ask.kind = SdoKind::upload_segment_request;
  ask.toggle = true;
  const Encoded a = encode_ok(ask);
  EXPECT_EQ(a.sdo()[0], 0x70);
  EXPECT_TRUE(decode_ok(a).sdo.toggle);
  Sdo ack;
  ack.kind = SdoKind::download_segment_response;
  ack.toggle = true;
  const Encoded k = encode_ok(ack);
  EXPECT_EQ(k.sdo()[0], 0x30);
  EXPECT_EQ(decode_ok(k).sdo.kind, SdoKind::download_segment_response);
}

TEST(CoeSdo, AbortCodesTravelIntactAndAreExplained) {
  const std::uint32_t codes[] = {abort_code::kObjectDoesNotExist, abort_code::kSubindexDoesNotExist, abort_code::kReadOnly,
                                 abort_code::kLengthMismatch, abort_code::kCannotTransferInState, abort_code::kToggleBit};
  for (std::uint32_t code : codes) {
    const Encoded e = encode_ok(abort(0x607A, 3, code));
    EXPECT_EQ(e.sdo()[0], 0x80);
    const Message m = decode_ok(e);
    // Aborts travel as "SDO request" in both directions (ETG.1000.6; IgH checks exactly this).
    EXPECT_EQ(m.service, Service::sdo_request);
    EXPECT_EQ(m.sdo.kind, SdoKind::abort);
    EXPECT_EQ(m.sdo.index, 0x607A);
    EXPECT_EQ(m.sdo.subindex, 3);
    EXPECT_EQ(m.sdo.abort_code, code);
    EXPECT_STRNE(explain_abort_code(code), "unknown abort code");
  }
  EXPECT_STREQ(explain_abort_code(abort_code::kObjectDoesNotExist), "object does not exist in the object dictionary");
}

TEST(CoeSdo, CompleteAccessBitIsKept) {
  const Message m = decode_ok(encode_ok(upload_request(0x1C12, 0, true)));
  EXPECT_TRUE(m.sdo.complete_access);
  // The upload response mirrors it: 0x51, as the LAN9252 answers SOEM (soem-single-lan9252.pcapng).
  const std::array<std::uint8_t, 6> whole{4, 0, 1, 2, 3, 4};
  Sdo r = upload_response(0x1C00, 0, ConstByteSpan(whole));
  r.complete_access = true;
  const auto bytes = encode_ok(r);
  EXPECT_EQ(bytes.sdo()[0], 0x51);
  const Message back = decode_ok(bytes);
  EXPECT_TRUE(back.sdo.complete_access);
  EXPECT_EQ(back.sdo.size, 6u);
}

TEST(CoeSdo, EncodeRefusesImpossibleExpeditedSizesAndSmallBuffers) {
  Sdo s = upload_response(0x1000, 0, ConstByteSpan());
  s.expedited = true;
  std::array<std::uint8_t, 64> buf{};
  EXPECT_EQ(encode(ByteSpan(buf), mbx::Header{}, s).error().code, Errc::invalid_argument);
  std::array<std::uint8_t, 15> small{};
  EXPECT_EQ(encode(ByteSpan(small), mbx::Header{}, upload_request(0x1000, 0)).error().code, Errc::capacity_exceeded);
}

TEST(CoeDecode, RefusesShortAndForeignMessages) {
  Encoded e = encode_ok(upload_request(0x1000, 0));
  // SDO part cut to 7 bytes.
  e.buf[0] = 9;
  auto r = decode(ConstByteSpan(e.buf.data(), 15));
  ASSERT_FALSE(r.ok());
  EXPECT_STREQ(r.error().what, "sdo header");
  // No room for the CoE header.
  e.buf[0] = 1;
  r = decode(ConstByteSpan(e.buf.data(), 7));
  ASSERT_FALSE(r.ok());
  EXPECT_STREQ(r.error().what, "coe header");
  // Not CoE.
  e.buf[0] = 10;
  e.buf[5] = 0x12;  // EoE
  r = decode(e.bytes());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::unsupported);
  EXPECT_STREQ(r.error().what, "not a CoE mailbox");
}

TEST(CoeDecode, BlockTransferCommandsAreUnsupported) {
  Encoded e = encode_ok(upload_request(0x1000, 0));
  e.buf[mbx::kHeaderSize + kCoeHeaderSize] = 0xA0;  // ccs 5: block upload
  auto r = decode(e.bytes());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::unsupported);
  EXPECT_STREQ(r.error().what, "sdo command");
  EXPECT_EQ(r.error().detail0, 5u);
}

TEST(CoeDecode, EmergencyFields) {
  std::array<std::uint8_t, 16> b{10, 0, 0, 0, 0, 0x03, 0x00, 0x10, 0x10, 0x42, 0x08, 1, 2, 3, 4, 5};
  auto r = decode(ConstByteSpan(b));
  ASSERT_TRUE(r.ok()) << r.error().what;
  EXPECT_EQ(r.value().service, Service::emergency);
  EXPECT_EQ(r.value().emergency.error_code, 0x4210);  // temperature
  EXPECT_EQ(r.value().emergency.error_register, 0x08);
  EXPECT_EQ(r.value().emergency.manufacturer[4], 5);
}

}  // namespace
}  // namespace rescue::ecat::coe
