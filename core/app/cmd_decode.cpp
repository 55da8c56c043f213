// rescue-motion decode FILE: one line per EtherCAT datagram of a pcap/pcapng capture.
#include "core/app/commands.hpp"

namespace rescue::app {
namespace {

int decode_main(const ParsedArgs& /*args*/) { return fail("decode", "not implemented yet"); }

}  // namespace

const CommandSpec kDecodeCommand{
    "decode", "decode FILE", "print every EtherCAT datagram of a pcap/pcapng capture, one line each",
    "Line format: frame command index address length wkc\n"
    "  frame   1-based frame number in the file\n"
    "  command mnemonic (NOP, APRD, ... FRMW)\n"
    "  index   datagram index, decimal\n"
    "  address 0xADP:0xADO for position/station/broadcast commands, 0xLLLLLLLL for logical ones\n"
    "  length  data length in bytes, decimal\n"
    "  wkc     working counter, decimal\n"
    "Frames that are not EtherCAT are skipped; malformed ones print 'frame ERROR reason'.",
    Span<const OptionSpec>(), 1, 1, decode_main};

}  // namespace rescue::app
