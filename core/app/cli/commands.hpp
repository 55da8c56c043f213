// The subcommands of rescue-motion (design brief section 7). Each lives in its own cmd_*.cpp and
// is listed once in main.cpp's table.
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

extern const CommandSpec kRunCommand;     // the firmware itself
extern const CommandSpec kSimCommand;     // serve the simulated segment on an interface
extern const CommandSpec kCtlCommand;     // operator client
extern const CommandSpec kDecodeCommand;  // list the datagrams of a capture
extern const CommandSpec kBenchCommand;   // measuring commands
extern const CommandSpec kDocsCommand;    // documentation printed from the firmware's tables

}  // namespace rescue::app
