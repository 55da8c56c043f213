// The master's CoE SDO Information codec (ecat/mailbox/coe_information.hpp): the three requests
// byte for byte as ETG.1000.6 5.6.3 (and SOEM) write them, the responses' fields and names, and every
// decoder refusing bytes too short for what it reads (a fragment without its header, descriptions
// without their fixed part, an OD list without its type or of an odd length).
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/coe_information.hpp"

namespace rescue::ecat::coe::info {
namespace {

using Bytes = std::vector<std::uint8_t>;

ConstByteSpan span(const Bytes& b) { return ConstByteSpan(b.data(), b.size()); }
std::string text(ConstByteSpan s) { return std::string(s.begin(), s.end()); }

TEST(CoeInformation, RequestsAreEncodedAsWholeMailboxMessages) {
  std::array<std::uint8_t, 32> out{};
  mbx::Header h;
  h.counter = 3;
  const Result<std::size_t> list = encode_request(ByteSpan(out), h, kGetOdListRequest, kListAll, 0);
  ASSERT_TRUE(list.ok());
  EXPECT_EQ(Bytes(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(list.value())),
            (Bytes{0x08, 0x00, 0x00, 0x00, 0x00, 0x33, 0x00, 0x80, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00}));
  const Result<std::size_t> entry = encode_request(ByteSpan(out), h, kGetEntryDescriptionRequest, 0x1018, 2);
  ASSERT_TRUE(entry.ok());
  EXPECT_EQ(Bytes(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(entry.value())),
            (Bytes{0x0A, 0x00, 0x00, 0x00, 0x00, 0x33, 0x00, 0x80, 0x05, 0x00, 0x00, 0x00, 0x18, 0x10, 0x02, 0x00}));
  // What the master sends, the CoE decoder reads as an SDO Information message of that opcode.
  const Result<Message> back = coe::decode(ConstByteSpan(out.data(), entry.value()));
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.value().service, Service::sdo_information);
  const Result<Fragment> f = decode_fragment(back.value().payload);
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f.value().opcode, kGetEntryDescriptionRequest);
  EXPECT_EQ(f.value().data.size(), 4U);

  EXPECT_FALSE(encode_request(ByteSpan(out), h, kGetOdListResponse, 1, 0).ok()) << "only the three requests";
  EXPECT_EQ(encode_request(ByteSpan(out.data(), 13), h, kGetOdListRequest, 1, 0).error().code, Errc::capacity_exceeded);
}

TEST(CoeInformation, FragmentsCarryTheirOpcodeIncompleteBitAndFragmentsLeft) {
  const Bytes first{0x82, 0x00, 0x02, 0x00, 0x01, 0x00, 0x00, 0x10};
  const Result<Fragment> f = decode_fragment(span(first));
  ASSERT_TRUE(f.ok());
  EXPECT_EQ(f.value().opcode, kGetOdListResponse);
  EXPECT_TRUE(f.value().incomplete);
  EXPECT_EQ(f.value().fragments_left, 2);
  EXPECT_EQ(f.value().data.size(), 4U);
  EXPECT_EQ(decode_fragment(ConstByteSpan(first.data(), 3)).error().code, Errc::truncated);
}

TEST(CoeInformation, DescriptionsGiveTheirFieldsAndTheRestAsTheName) {
  const Bytes object{0x18, 0x10, 0x23, 0x00, 0x04, 0x09, 'I', 'd', 'e', 'n', 't', 'i', 't', 'y'};
  const Result<ObjectDescription> o = decode_object_description(span(object));
  ASSERT_TRUE(o.ok());
  EXPECT_EQ(o.value().index, 0x1018);
  EXPECT_EQ(o.value().data_type, 0x0023);
  EXPECT_EQ(o.value().max_subindex, 4);
  EXPECT_STREQ(object_code_name(o.value().object_code), "RECORD");
  EXPECT_EQ(text(o.value().name), "Identity");
  EXPECT_EQ(decode_object_description(ConstByteSpan(object.data(), 5)).error().code, Errc::truncated);
  const Result<ObjectDescription> unnamed = decode_object_description(ConstByteSpan(object.data(), 6));
  ASSERT_TRUE(unnamed.ok());
  EXPECT_TRUE(unnamed.value().name.empty());

  const Bytes entry{0x41, 0x60, 0x00, 0x00, 0x06, 0x00, 0x10, 0x00, 0x87, 0x00, 'S', 't', 'a', 't', 'u', 's'};
  const Result<EntryDescription> e = decode_entry_description(span(entry));
  ASSERT_TRUE(e.ok());
  EXPECT_EQ(e.value().index, 0x6041);
  EXPECT_EQ(e.value().subindex, 0);
  EXPECT_STREQ(data_type_name(e.value().data_type), "UNSIGNED16");
  EXPECT_EQ(e.value().bit_length, 16);
  char access[7];
  access_text(e.value().access, access);
  EXPECT_STREQ(access, "r-r-r-");  // 0x87: read in every state, TxPDO-mappable
  access_text(0x003F, access);
  EXPECT_STREQ(access, "rwrwrw");
  access_text(0x000F, access);
  EXPECT_STREQ(access, "rwr-r-");  // written in PRE-OP only
  EXPECT_EQ(text(e.value().name), "Status");
  EXPECT_EQ(decode_entry_description(ConstByteSpan(entry.data(), 9)).error().code, Errc::truncated);
  EXPECT_STREQ(data_type_name(0x7777), "?");
  EXPECT_STREQ(object_code_name(3), "?");
}

TEST(CoeInformation, AnOdListIsItsTypeThenEvenIndexes) {
  const Bytes list{0x01, 0x00, 0x00, 0x10, 0x18, 0x10, 0x41, 0x60};
  const Result<OdList> l = decode_od_list(span(list));
  ASSERT_TRUE(l.ok());
  EXPECT_EQ(l.value().list_type, kListAll);
  ASSERT_EQ(l.value().count, 3U);
  EXPECT_EQ(l.value().index(0), 0x1000);
  EXPECT_EQ(l.value().index(2), 0x6041);
  EXPECT_EQ(l.value().index(3), 0) << "past the list";
  EXPECT_EQ(decode_od_list(ConstByteSpan(list.data(), 1)).error().code, Errc::truncated);
  EXPECT_EQ(decode_od_list(ConstByteSpan(list.data(), 7)).error().code, Errc::malformed);
  const Result<OdList> empty = decode_od_list(ConstByteSpan(list.data(), 2));
  ASSERT_TRUE(empty.ok());
  EXPECT_EQ(empty.value().count, 0U);
}

}  // namespace
}  // namespace rescue::ecat::coe::info
