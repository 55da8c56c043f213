#include "core/app/cli/esi_xml.hpp"

#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <string_view>

namespace rescue::app {
namespace {

using ecat::sii::Pdo;
using ecat::sii::PdoEntry;
using ecat::sii::Sii;
using ecat::sii::SyncManagerType;

// The escaped form of one byte of an SII string (docs/operator.md "ESI from the SII").
void escape_char(unsigned char c, char (&out)[12]) noexcept {
  switch (c) {
    case '&': (void)std::snprintf(out, sizeof out, "&amp;"); return;
    case '<': (void)std::snprintf(out, sizeof out, "&lt;"); return;
    case '>': (void)std::snprintf(out, sizeof out, "&gt;"); return;
    case '"': (void)std::snprintf(out, sizeof out, "&quot;"); return;
    case '\'': (void)std::snprintf(out, sizeof out, "&apos;"); return;
    default: break;
  }
  if (c >= 0x20 && c < 0x7F) {
    out[0] = static_cast<char>(c);
    out[1] = '\0';
  } else if (c >= 0xA0) {
    (void)std::snprintf(out, sizeof out, "&#x%02X;", c);  // Latin-1
  } else {
    (void)std::snprintf(out, sizeof out, "&#xFFFD;");  // a control byte: no XML 1.0 character
  }
}

// Appends to a fixed buffer; once something did not fit, nothing more is written and fits() is false.
class XmlWriter {
 public:
  explicit XmlWriter(Span<char> out) noexcept : out_(out) {
    if (out_.size() > 0) out_.data()[0] = '\0';
  }
  // NOLINTNEXTLINE(cert-dcl50-cpp): printf-style, checked by its format attribute
  void line(int depth, const char* format, ...) noexcept __attribute__((format(printf, 3, 4))) {
    for (int i = 0; i < depth; ++i) raw("  ");
    std::va_list args;
    va_start(args, format);
    formatted(format, args);
    va_end(args);
    raw("\n");
  }
  void raw(const char* text) noexcept { append(text, std::strlen(text)); }
  void escaped(std::string_view text) noexcept {
    for (const char c : text) {
      char e[12];
      escape_char(static_cast<unsigned char>(c), e);
      raw(e);
    }
  }
  // <tag>escaped text</tag> on a line of its own.
  void element(int depth, const char* tag, std::string_view text) noexcept {
    for (int i = 0; i < depth; ++i) raw("  ");
    raw("<");
    raw(tag);
    raw(">");
    escaped(text);
    raw("</");
    raw(tag);
    raw(">\n");
  }
  bool fits() const noexcept { return fits_; }
  std::size_t used() const noexcept { return used_; }

 private:
  void formatted(const char* format, std::va_list args) noexcept __attribute__((format(printf, 2, 0))) {
    char text[256];
    // The analyzer loses va_start across the call from line() (as in hal/files/trusted_file.cpp).
    const int n = std::vsnprintf(text, sizeof text, format, args);  // NOLINT(clang-analyzer-valist.Uninitialized)
    if (n < 0 || static_cast<std::size_t>(n) >= sizeof text) {
      fits_ = false;
      return;
    }
    append(text, static_cast<std::size_t>(n));
  }
  void append(const char* text, std::size_t n) noexcept {
    if (!fits_ || used_ + n + 1 > out_.size()) {
      fits_ = false;
      return;
    }
    std::memcpy(out_.data() + used_, text, n);
    used_ += n;
    out_.data()[used_] = '\0';
  }
  Span<char> out_;
  std::size_t used_{0};
  bool fits_{true};
};

// ESI's names of the CoE base data types (ETG.1000.6 table 64) an SII PDO entry may name.
const char* data_type_name(std::uint8_t type) noexcept {
  switch (type) {
    case 0x01: return "BOOL";
    case 0x02: return "SINT";
    case 0x03: return "INT";
    case 0x04: return "DINT";
    case 0x05: return "USINT";
    case 0x06: return "UINT";
    case 0x07: return "UDINT";
    case 0x08: return "REAL";
    case 0x09: return "STRING";
    case 0x0A: return "ARRAY [0..n] OF BYTE";
    case 0x11: return "LREAL";
    case 0x15: return "LINT";
    case 0x1B: return "ULINT";
    default: return nullptr;
  }
}

const char* sync_manager_text(SyncManagerType type) noexcept {
  switch (type) {
    case SyncManagerType::mailbox_out: return "MBoxOut";
    case SyncManagerType::mailbox_in: return "MBoxIn";
    case SyncManagerType::outputs: return "Outputs";
    case SyncManagerType::inputs: return "Inputs";
    case SyncManagerType::unused: break;
  }
  return nullptr;
}

// SII PDO flags (ETG.2010, as ESI's attributes): bit 0 PdoMandatory, bit 4 PdoFixedContent.
constexpr std::uint16_t kPdoMandatory = 0x0001;
constexpr std::uint16_t kPdoFixedContent = 0x0010;

// String `index` of the SII, or "" when it is one the master did not read (strings skipped: only
// the General category's group, order and device name were read whole; the rest reads 0 or is cut).
std::string_view read_string(const Sii& sii, std::uint8_t index, bool strings_skipped) noexcept {
  return strings_skipped ? std::string_view() : sii.string(index);
}

void write_pdos(XmlWriter& w, const Sii& sii, const char* tag, Span<const Pdo> pdos, bool tx, bool skipped) noexcept {
  for (const Pdo& pdo : pdos) {
    char attributes[64] = "";
    if (pdo.sync_manager != 0xFF) (void)std::snprintf(attributes, sizeof attributes, " Sm=\"%u\"", pdo.sync_manager);
    w.line(4, "<%s%s%s%s>", tag, attributes, (pdo.flags & kPdoFixedContent) != 0 ? " Fixed=\"1\"" : "",
           (pdo.flags & kPdoMandatory) != 0 ? " Mandatory=\"1\"" : "");
    w.line(5, "<Index>#x%04" PRIx16 "</Index>", pdo.index);
    w.element(5, "Name", read_string(sii, pdo.name_index, skipped));
    for (const PdoEntry& e : tx ? sii.tx_entries_of(pdo) : sii.rx_entries_of(pdo)) {
      w.line(5, "<Entry>");
      w.line(6, "<Index>#x%04" PRIx16 "</Index>", e.index);
      if (e.index != 0) w.line(6, "<SubIndex>%u</SubIndex>", e.subindex);  // index 0: a gap, no object
      w.line(6, "<BitLen>%u</BitLen>", e.bit_length);
      if (e.index != 0) {
        w.element(6, "Name", read_string(sii, e.name_index, skipped));
        const char* type = data_type_name(e.data_type);
        if (type != nullptr) w.element(6, "DataType", type);
      }
      w.line(5, "</Entry>");
    }
    w.line(4, "</%s>", tag);
  }
}

void write_device(XmlWriter& w, const Sii& sii, bool skipped) noexcept {
  w.line(2, "<Devices>");
  w.line(3, "<Device>");
  // The Type's text is the order code (the device name when the SII names none).
  char type[96];
  (void)std::snprintf(type, sizeof type, "        <Type ProductCode=\"#x%08" PRIx32 "\" RevisionNo=\"#x%08" PRIx32 "\">",
                      sii.identity.product_code, sii.identity.revision);
  w.raw(type);
  w.escaped(sii.order().empty() ? sii.name() : sii.order());
  w.raw("</Type>\n");
  w.element(4, "Name", sii.name());
  if (!sii.group().empty()) w.element(4, "GroupType", sii.group());
  for (const ecat::sii::FmmuUsage f : sii.fmmus) {
    const char* usage = f == ecat::sii::FmmuUsage::outputs   ? "Outputs"
                        : f == ecat::sii::FmmuUsage::inputs  ? "Inputs"
                        : f == ecat::sii::FmmuUsage::sync_manager_status ? "MBoxState"
                                                                        : nullptr;
    if (usage != nullptr) w.element(4, "Fmmu", usage);
  }
  for (const ecat::sii::SyncManager& sm : sii.sync_managers) {
    const char* text = sync_manager_text(sm.type);
    w.line(4, "<Sm StartAddress=\"#x%04" PRIx16 "\" ControlByte=\"#x%02x\" DefaultSize=\"%u\" Enable=\"%u\">%s</Sm>",
           sm.start_address, sm.control, sm.length, sm.enable & 1U, text != nullptr ? text : "");
  }
  write_pdos(w, sii, "RxPdo", Span<const Pdo>(sii.rx_pdos.data(), sii.rx_pdos.size()), false, skipped);
  write_pdos(w, sii, "TxPdo", Span<const Pdo>(sii.tx_pdos.data(), sii.tx_pdos.size()), true, skipped);
  if (sii.standard_mailbox.present()) {
    w.line(4, "<Mailbox>");
    if (sii.supports(ecat::sii::kMailboxCoE)) {
      const std::uint8_t d = sii.has_general ? sii.general.coe_details : 0;
      w.line(5, R"(<CoE SdoInfo="%d" PdoAssign="%d" PdoConfig="%d" CompleteAccess="%d"/>)",
             (d & ecat::sii::kCoeDetailSdoInfo) != 0, (d & ecat::sii::kCoeDetailPdoAssign) != 0,
             (d & ecat::sii::kCoeDetailPdoConfig) != 0, (d & ecat::sii::kCoeDetailSdoCompleteAccess) != 0);
    }
    if (sii.supports(ecat::sii::kMailboxEoE)) w.line(5, "<EoE/>");
    if (sii.supports(ecat::sii::kMailboxFoE)) w.line(5, "<FoE/>");
    if (sii.supports(ecat::sii::kMailboxSoE)) w.line(5, "<SoE/>");
    w.line(4, "</Mailbox>");
  }
  if (!sii.dc_modes.empty()) {
    w.line(4, "<Dc>");
    for (const ecat::sii::DcMode& dc : sii.dc_modes) {
      w.line(5, "<OpMode>");
      w.element(6, "Name", read_string(sii, dc.name_index, skipped));
      w.element(6, "Desc", read_string(sii, dc.description_index, skipped));
      w.line(6, "<AssignActivate>#x%04" PRIx16 "</AssignActivate>", dc.assign_activate);
      w.line(6, "<CycleTimeSync0 Factor=\"%d\">%" PRIu32 "</CycleTimeSync0>", dc.sync0_cycle_factor, dc.cycle_time0);
      w.line(6, "<ShiftTimeSync0>%" PRIu32 "</ShiftTimeSync0>", dc.shift_time0);
      w.line(6, "<CycleTimeSync1 Factor=\"%d\"/>", dc.sync1_cycle_factor);  // the SII holds no cycle time 1
      w.line(6, "<ShiftTimeSync1>%" PRIu32 "</ShiftTimeSync1>", dc.shift_time1);
      w.line(5, "</OpMode>");
    }
    w.line(4, "</Dc>");
  }
  w.line(4, "<Eeprom>");
  w.line(5, "<ByteSize>%" PRIu32 "</ByteSize>", sii.eeprom_size_bytes);
  // The configuration area's words 0..4 as the EEPROM holds them (little-endian), as ESI writes it.
  const std::uint16_t words[] = {sii.config.pdi_control, sii.config.pdi_config, sii.config.sync_impulse_length,
                                 sii.config.pdi_config2, sii.config.station_alias};
  char config[32] = "";
  std::size_t at = 0;
  for (const std::uint16_t word : words) {
    at += static_cast<std::size_t>(std::snprintf(config + at, sizeof config - at, "%02X%02X", word & 0xFFU, word >> 8U));
  }
  w.line(5, "<ConfigData>%s</ConfigData>", config);
  w.line(4, "</Eeprom>");
  w.line(3, "</Device>");
  w.line(2, "</Devices>");
}

}  // namespace

std::size_t xml_escape(const char* text, std::size_t length, Span<char> out) noexcept {
  XmlWriter w(out);
  w.escaped(std::string_view(text, length));
  return w.fits() ? w.used() : 0;
}

std::size_t write_esi_xml(const Sii& sii, const EsiSource& source, Span<char> out) noexcept {
  XmlWriter w(out);
  w.raw("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- Slave ");
  char position[24];
  (void)std::snprintf(position, sizeof position, "%zu (", source.position);
  w.raw(position);
  w.escaped(source.slave_name);  // the plan's own name (no "--", which a comment may not hold)
  w.raw("): built by rescue-motion from the SII the master read at bring-up -->\n");
  if (source.strings_skipped) w.raw("<!-- the master did not read the PDO, entry and DC mode names of the SII: they are left empty -->\n");
  w.line(0, "<EtherCATInfo>");
  w.line(1, "<Vendor>");
  w.line(2, "<Id>#x%08" PRIx32 "</Id>", sii.identity.vendor_id);
  w.line(1, "</Vendor>");
  w.line(1, "<Descriptions>");
  if (!sii.group().empty()) {
    w.line(2, "<Groups>");
    w.line(3, "<Group>");
    w.element(4, "Type", sii.group());
    w.element(4, "Name", sii.group());
    w.line(3, "</Group>");
    w.line(2, "</Groups>");
  }
  write_device(w, sii, source.strings_skipped);
  w.line(1, "</Descriptions>");
  w.line(0, "</EtherCATInfo>");
  return w.fits() ? w.used() : 0;
}

}  // namespace rescue::app
