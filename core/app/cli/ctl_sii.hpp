// ctl sii_read SLAVE [--raw] and ctl xml SLAVE (docs/operator.md "SII"): the slave's SII image as the master read it from
// its EEPROM at bring-up, like IgH's `ethercat sii_read`: a hex dump (offset, 16 bytes, their
// printable characters), with --raw the bytes themselves on stdout, with --json one object (the
// bytes as hex). SLAVE: a slave's name (ctl slaves) or its position. The robot answers from the
// copy its EtherCAT handler published after bring-up, in chunks of 512 bytes (get_sii, sii).
#pragma once

#include "core/app/cli/ctl_verbs.hpp"
#include "core/app/config/command_line.hpp"

namespace rescue::app {

// CtlConverse: asks for the chunks until the image is whole, then prints it; returns the exit status.
int ctl_sii_read(const ParsedArgs& args, CtlPeer& peer) noexcept;

// ctl xml SLAVE (docs/operator.md "ESI from the SII"): the same image, parsed here in ctl
// (ecat/sii/sii.hpp) and written as an ESI-style description (esi_xml.hpp), like IgH's
// `ethercat xml`; --json: the XML as one string. A slave whose SII does not parse is refused with
// the parser's reason.
int ctl_xml(const ParsedArgs& args, CtlPeer& peer) noexcept;

}  // namespace rescue::app
