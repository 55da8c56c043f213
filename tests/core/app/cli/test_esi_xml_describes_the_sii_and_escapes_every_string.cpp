// ctl xml's description (core/app/cli/esi_xml.hpp, docs/operator.md "ESI from the SII"): from the
// joint drive's SII image (the simulator's, parsed by the master's parser) it names the vendor,
// product, revision, device name and group, each sync manager, each PDO with its entries and data
// types, the mailbox, the DC modes and the EEPROM size; every string of the SII is XML-escaped; a
// description that does not fit the buffer is refused, not cut.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <string>

#include "core/app/cli/esi_xml.hpp"
#include "drivers/joint/device_identity.hpp"
#include "drivers/sim/devices/joint_drive_sii.hpp"
#include "drivers/sim/devices/minimal_sii.hpp"
#include "ecat/sii/sii.hpp"

namespace rescue::app {
namespace {

std::array<char, 1U << 17U> g_xml;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(EsiXml, TheJointDrivesSiiBecomesItsDescription) {
  const Result<drivers::SiiImage> image = drivers::build_joint_drive_sii(3);
  ASSERT_TRUE(image.ok());
  const Result<ecat::sii::Sii> sii = ecat::sii::Sii::parse(ConstByteSpan(image.value()));
  ASSERT_TRUE(sii.ok()) << sii.error().what;
  EsiSource source;
  source.slave_name = "l_elbow";
  source.position = 3;
  const std::size_t n = write_esi_xml(sii.value(), source, Span<char>(g_xml));
  ASSERT_GT(n, 0U);
  const std::string xml(g_xml.data(), n);
  EXPECT_EQ(xml.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n", 0), 0U) << xml;
  char vendor[32];
  (void)std::snprintf(vendor, sizeof vendor, "<Id>#x%08x</Id>", drivers::kJointDriveIdentity.vendor_id);
  EXPECT_NE(xml.find(vendor), std::string::npos) << xml;
  EXPECT_NE(xml.find("<Type ProductCode=\"#x4a443432\" RevisionNo=\"#x00010000\">"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<Name>" + std::string(sii.value().name()) + "</Name>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<GroupType>Drives</GroupType>"), std::string::npos) << xml;
  EXPECT_EQ(count(xml, "<Sm "), sii.value().sync_managers.size()) << xml;
  EXPECT_NE(xml.find(">MBoxOut</Sm>"), std::string::npos) << xml;
  EXPECT_NE(xml.find(">Inputs</Sm>"), std::string::npos) << xml;
  EXPECT_EQ(count(xml, "<RxPdo"), sii.value().rx_pdos.size());
  EXPECT_EQ(count(xml, "<TxPdo"), sii.value().tx_pdos.size());
  EXPECT_EQ(count(xml, "<Entry>"), sii.value().rx_entries.size() + sii.value().tx_entries.size());
  EXPECT_EQ(count(xml, "<Entry>"), count(xml, "</Entry>"));
  EXPECT_NE(xml.find("<RxPdo Sm=\"2\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("<Index>#x1600</Index>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<Index>#x6040</Index>"), std::string::npos) << "the controlword\n" << xml;
  EXPECT_NE(xml.find("<DataType>UINT</DataType>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<CoE SdoInfo="), std::string::npos) << xml;
  EXPECT_NE(xml.find("<AssignActivate>#x0300</AssignActivate>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<ByteSize>2048</ByteSize>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<!-- Slave 3 (l_elbow)"), std::string::npos) << xml;
  EXPECT_EQ(xml.find("did not read"), std::string::npos) << "every string was read";
  source.strings_skipped = true;
  const std::string skipped(g_xml.data(), write_esi_xml(sii.value(), source, Span<char>(g_xml)));
  EXPECT_NE(skipped.find("did not read the PDO, entry and DC mode names"), std::string::npos) << skipped;
  // Names the master did not read are left empty (a half-read one would be garbage); the device's stays.
  EXPECT_NE(skipped.find("<Index>#x1600</Index>\n          <Name></Name>"), std::string::npos) << skipped;
  EXPECT_NE(skipped.find("<Name>" + std::string(sii.value().name()) + "</Name>"), std::string::npos) << skipped;
  EXPECT_EQ(xml.find("<Index>#x1600</Index>\n          <Name></Name>"), std::string::npos) << "read: named\n" << xml;
  EXPECT_EQ(count(xml, "</EtherCATInfo>"), 1U);
}

TEST(EsiXml, EveryStringOfTheSiiIsEscaped) {
  // A device name with each character XML gives a meaning, a control byte and a Latin-1 letter.
  const char* name = "A<&>\"'\x01\xE9--Z";
  std::array<std::uint8_t, 512> image{};
  drivers::SiiIdentity identity;
  identity.vendor_id = 0x00000ABC;
  identity.product_code = 0x1234;
  const Result<std::size_t> size = drivers::build_minimal_sii(ByteSpan(image), identity, name);
  ASSERT_TRUE(size.ok());
  const Result<ecat::sii::Sii> sii = ecat::sii::Sii::parse(ConstByteSpan(image.data(), size.value()));
  ASSERT_TRUE(sii.ok()) << sii.error().what;
  const std::size_t n = write_esi_xml(sii.value(), EsiSource{}, Span<char>(g_xml));
  ASSERT_GT(n, 0U);
  const std::string xml(g_xml.data(), n);
  const std::string escaped = "A&lt;&amp;&gt;&quot;&apos;&#xFFFD;&#xE9;--Z";
  EXPECT_NE(xml.find("<Name>" + escaped + "</Name>"), std::string::npos) << xml;
  EXPECT_NE(xml.find(">" + escaped + "</Type>"), std::string::npos) << "the order code too\n" << xml;
  EXPECT_EQ(xml.find("A<&"), std::string::npos) << xml;
  EXPECT_EQ(xml.find('\x01'), std::string::npos) << xml;
  EXPECT_EQ(xml.find('\xE9'), std::string::npos) << xml;
  EXPECT_EQ(xml.find("<Mailbox>"), std::string::npos) << "no mailbox in this SII";

  std::array<char, 64> small{};
  EXPECT_EQ(xml_escape(name, std::strlen(name), Span<char>(small)), escaped.size());
  EXPECT_EQ(std::string(small.data()), escaped);
}

TEST(EsiXml, ADescriptionThatDoesNotFitIsRefusedNotCut) {
  const Result<drivers::SiiImage> image = drivers::build_joint_drive_sii(3);
  ASSERT_TRUE(image.ok());
  const Result<ecat::sii::Sii> sii = ecat::sii::Sii::parse(ConstByteSpan(image.value()));
  ASSERT_TRUE(sii.ok());
  std::array<char, 512> small{};
  EXPECT_EQ(write_esi_xml(sii.value(), EsiSource{}, Span<char>(small)), 0U);
  std::array<char, 4> tiny{};
  EXPECT_EQ(xml_escape("&&&", 3, Span<char>(tiny)), 0U);
}

}  // namespace
}  // namespace rescue::app
