// ctl upload / ctl download (docs/operator.md "SDO"): a CoE SDO transfer to one slave through the
// robot's EtherCAT handler, like IgH's `ethercat upload/download`.
//
//   ctl upload SLAVE INDEX:SUB [--type T]          prints the value: a number in hex and decimal,
//                                                  a string, or hex bytes
//   ctl download SLAVE INDEX:SUB VALUE [--type T]  writes VALUE
//
// SLAVE is a joint's name (its drive), a slave's name (ctl slaves: the junctions too) or a slave's
// position (0 is the first slave in frame order), as IgH's `-p POSITION`.
// INDEX and SUB are hexadecimal (0x optional), as an object is written in ESI files and drive
// manuals: 0x100A:00. --type is u8, u16, u32, i8, i16, i32, string or hex (bytes, e.g. 0a0b0c).
// Without --type an upload is shown by its size (1, 2, 4 bytes: unsigned; else a string when it is
// printable text, hex bytes otherwise), and a download first uploads the object to learn its size
// (1, 2, 4 bytes: a number of that width, signed when VALUE is negative; else a string).
#pragma once

#include <cstddef>

#include "core/app/config/command_line.hpp"
#include "core/app/links/protocol_messages.hpp"
#include "core/app/cli/ctl_verbs.hpp"
#include "core/base/result.hpp"

namespace rescue::app {

// SLAVE of an SDO verb (upload, download, sdos, pdos): a joint's name (its drive), a slave's name
// (the junctions too) or a slave's position, into sdo's target, joint and slave. Errors:
// invalid_argument with the text for the user.
Status parse_sdo_slave(const char* name, protocol::SdoPayload& sdo) noexcept;
// The position of the slave an SDO target names (kSlaveCount: none).
std::size_t sdo_slave_position(protocol::SdoTarget target, std::uint8_t joint, std::uint8_t slave) noexcept;

// The sdo_upload / sdo_download request of `verb` and its arguments. `peer`: for a download
// without --type, the robot is asked for the object's current value first (its size).
// Errors: invalid_argument with the text for the user; an error of that first exchange.
Result<protocol::Message> build_sdo_request(const ParsedArgs& args, CtlPeer& peer) noexcept;

// Prints an sdo_result (text, or one JSON object with --json); returns ctl's exit status
// (0: the transfer was done; refused: the drive aborted or the robot refused; usage: a fixed-size
// --type that the uploaded object's size does not fit).
int print_sdo_result(const protocol::Message& request, const protocol::Message& answer) noexcept;

}  // namespace rescue::app
