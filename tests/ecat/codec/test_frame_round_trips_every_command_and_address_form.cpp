// Every one of the fifteen commands, with every address form it can carry, survives build -> parse
// with all fields intact (command, index, address halves or logical address, length, more-follows,
// IRQ, data, working counter).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "ecat/codec/frame.hpp"

namespace rescue::ecat {
namespace {

struct AddressCase {
  const char* name;
  std::uint32_t address;
};

// Addresses that exercise each form at its edges.
std::vector<AddressCase> addresses_for(AddressKind kind) {
  switch (kind) {
    case AddressKind::position:
      return {{"first slave", make_address(position_adp(0), 0x0130)},
              {"slave 22", make_address(position_adp(22), 0x0910)},
              {"last position", make_address(position_adp(0xFFFF), 0xFFFF)}};
    case AddressKind::station:
      return {{"station 0x1000", make_address(0x1000, 0x0120)},
              {"station 0xFFFF", make_address(0xFFFF, 0x0000)},
              {"station 0", make_address(0x0000, 0x1000)}};
    case AddressKind::broadcast:
      return {{"broadcast", make_address(0x0000, 0x0130)}, {"broadcast adp 23", make_address(23, 0x0900)}};
    case AddressKind::logical:
      return {{"logical 0", 0x00000000U}, {"logical 0x00010000", 0x00010000U}, {"logical max", 0xFFFFFFFFU}};
    case AddressKind::none:
      return {{"nop zero", 0}, {"nop arbitrary", 0xDEADBEEFU}};
  }
  return {};
}

std::vector<std::uint8_t> pattern(std::size_t n, std::uint8_t seed) {
  std::vector<std::uint8_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint8_t>(seed + i * 7);
  return v;
}

TEST(FrameRoundTrip, EveryCommandWithEveryAddressForm) {
  int cases = 0;
  for (std::uint8_t raw = 0; raw < kCommandCount; ++raw) {
    const auto command = static_cast<Command>(raw);
    for (const AddressCase& a : addresses_for(address_kind(command))) {
      for (const std::uint16_t length : {std::uint16_t{0}, std::uint16_t{1}, std::uint16_t{8}, std::uint16_t{300}}) {
        SCOPED_TRACE(testing::Message() << mnemonic(command) << " " << a.name << " len " << length);
        const std::vector<std::uint8_t> data = pattern(length, raw);
        FrameBuilder b;
        b.reset(MacAddress{0x02, 0, 0, 0, 0, 0x01});
        const auto slot = b.add(command, static_cast<std::uint8_t>(0xF0 + raw), a.address, length,
                                ConstByteSpan(data.data(), data.size()), 0xA55A, 0x1234);
        ASSERT_TRUE(slot.ok()) << slot.error().what;
        const ConstByteSpan frame = b.finish();

        const auto parsed = FrameView::parse(frame);
        ASSERT_TRUE(parsed.ok()) << parsed.error().what;
        ASSERT_EQ(parsed.value().datagram_count(), 1U);
        const DatagramView d = *parsed.value().begin();
        EXPECT_EQ(d.command(), command);
        EXPECT_EQ(d.index(), 0xF0 + raw);
        EXPECT_EQ(d.address(), a.address);
        EXPECT_EQ(d.adp(), address_adp(a.address));
        EXPECT_EQ(d.ado(), address_ado(a.address));
        EXPECT_EQ(d.length(), length);
        EXPECT_FALSE(d.more_follows());
        EXPECT_FALSE(d.circulating());
        EXPECT_EQ(d.irq(), 0xA55A);
        EXPECT_EQ(d.wkc(), 0x1234);
        ASSERT_EQ(d.data().size(), length);
        EXPECT_TRUE(std::equal(data.begin(), data.end(), d.data().begin()));
        EXPECT_EQ(parsed.value().header().ecat_end(), kEthernetHeaderSize + kEcatHeaderSize + kDatagramOverhead + length);
        ++cases;
      }
    }
  }
  EXPECT_EQ(cases, 4 * (2 + 4 * 3 + 4 * 3 + 3 * 2 + 3 * 3));
}

TEST(FrameRoundTrip, AllFifteenCommandsInOneFrameKeepOrderAndMoreFollows) {
  FrameBuilder b;
  b.reset(MacAddress{0x02, 0, 0, 0, 0, 0x01}, MacAddress{0x01, 0x01, 0x05, 0x01, 0, 0});
  for (std::uint8_t raw = 0; raw < kCommandCount; ++raw) {
    const std::vector<std::uint8_t> data = pattern(raw, raw);
    ASSERT_TRUE(b.add(static_cast<Command>(raw), raw, 0x01000000U * raw + raw, raw, ConstByteSpan(data.data(), data.size()),
                      raw, static_cast<std::uint16_t>(raw * 3))
                    .ok());
  }
  const auto parsed = FrameView::parse(b.finish());
  ASSERT_TRUE(parsed.ok()) << parsed.error().what;
  const FrameHeader& h = parsed.value().header();
  EXPECT_EQ(h.destination, (MacAddress{0x01, 0x01, 0x05, 0x01, 0, 0}));
  EXPECT_EQ(h.source, (MacAddress{0x02, 0, 0, 0, 0, 0x01}));
  EXPECT_FALSE(h.vlan_tagged);
  EXPECT_EQ(h.ecat_type, kEcatTypeDatagrams);
  ASSERT_EQ(parsed.value().datagram_count(), kCommandCount);
  std::uint8_t i = 0;
  for (const DatagramView d : parsed.value()) {
    EXPECT_EQ(d.index_in_frame(), i);
    EXPECT_EQ(d.command(), static_cast<Command>(i));
    EXPECT_EQ(d.index(), i);
    EXPECT_EQ(d.address(), 0x01000000U * i + i);
    EXPECT_EQ(d.length(), i);
    EXPECT_EQ(d.irq(), i);
    EXPECT_EQ(d.wkc(), i * 3);
    EXPECT_EQ(d.more_follows(), i + 1 < kCommandCount);
    ++i;
  }
  EXPECT_EQ(i, kCommandCount);
}

TEST(FrameRoundTrip, MnemonicsRoundTripAndMatchAddressKinds) {
  const std::array<const char*, kCommandCount> names{"NOP", "APRD", "APWR", "APRW", "FPRD", "FPWR", "FPRW", "BRD",
                                                     "BWR", "BRW",  "LRD",  "LWR",  "LRW",  "ARMW", "FRMW"};
  for (std::uint8_t raw = 0; raw < kCommandCount; ++raw) {
    const auto c = static_cast<Command>(raw);
    EXPECT_STREQ(mnemonic(c), names[raw]);
    Command back{};
    ASSERT_TRUE(command_from_mnemonic(names[raw], back));
    EXPECT_EQ(back, c);
  }
  EXPECT_STREQ(mnemonic(static_cast<Command>(15)), "?");
  Command unused{};
  EXPECT_FALSE(command_from_mnemonic("LRWX", unused));
  EXPECT_EQ(address_kind(Command::ARMW), AddressKind::position);
  EXPECT_EQ(address_kind(Command::FRMW), AddressKind::station);
  EXPECT_EQ(address_kind(Command::BRW), AddressKind::broadcast);
  EXPECT_EQ(address_kind(Command::LRW), AddressKind::logical);
  EXPECT_EQ(address_kind(Command::NOP), AddressKind::none);
}

TEST(FrameRoundTrip, MutableViewEditsSurviveReparse) {
  FrameBuilder b;
  ASSERT_TRUE(b.add(Command::APRD, 1, make_address(position_adp(3), 0x0000), 2).ok());
  ASSERT_TRUE(b.add(Command::BRD, 2, make_address(0, 0x0130), 2).ok());
  const ConstByteSpan built = b.finish();
  std::vector<std::uint8_t> copy(built.begin(), built.end());
  auto parsed = MutableFrameView::parse(ByteSpan(copy.data(), copy.size()));
  ASSERT_TRUE(parsed.ok());
  for (const MutableDatagramView d : parsed.value()) {
    d.set_adp(static_cast<std::uint16_t>(d.adp() + 1));  // what a passing slave does
    d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 1));
    d.set_circulating(true);
    d.data()[0] = 0x42;
  }
  const auto again = FrameView::parse(ConstByteSpan(copy.data(), copy.size()));
  ASSERT_TRUE(again.ok());
  auto it = again.value().begin();
  EXPECT_EQ((*it).adp(), static_cast<std::uint16_t>(position_adp(3) + 1));
  EXPECT_TRUE((*it).circulating());
  EXPECT_TRUE((*it).more_follows());  // circulating does not disturb the neighbouring bits
  EXPECT_EQ((*it).length(), 2);
  ++it;
  EXPECT_EQ((*it).adp(), 1);
  EXPECT_EQ((*it).wkc(), 1);
  EXPECT_EQ((*it).data()[0], 0x42);
}

}  // namespace
}  // namespace rescue::ecat
