// Fault injection as text, for a running simulator (`rescue-motion sim`, an operator console, a
// test script): one command per line, slaves by name (as in kSlaves) or auto-increment position.
//
//   cut SLAVE            cut the cable into SLAVE's port 0 (SLAVE and everything behind it drop off;
//                        on a ring the slaves behind answer the ring port's frames instead)
//   restore SLAVE        reconnect it
//   cut ring, restore ring, replace-cable ring   the same for the ring-return cable (ring segments:
//                        from the last slave's free port to the master's ring port; refused on a tree)
//   freeze SLAVE         hang SLAVE's application (the ESC keeps forwarding and answering)
//   thaw SLAVE           let it run again
//   power-off SLAVE      SLAVE dies (links down on both sides)
//   power-on SLAVE       SLAVE starts again, fresh, in INIT
//   drop N               lose the next N frames on their way back
//   corrupt N            flip one bit in each of the next N frames
//   drive-fault SLAVE CODE   raise a device fault with error code CODE (decimal or 0x hex)
//   power-cycle SLAVE    SLAVE off and on at once: registers and station address lost, INIT, SII kept
//   replace-cable SLAVE  the cable into SLAVE's port 0 goes down and up (slaves keep their power)
//   foreign SLAVE        a device of another type (other SII product code) plugged in SLAVE's place
//   original SLAVE       the planned device plugged back in SLAVE's place
//   corrupt-port SLAVE PORT N   damage the next N frames received on SLAVE's PORT (0..3): error counters
//   half-mapped SLAVE    SLAVE's RxPDO mapping left half-written (0x1600 entries written, 0x1600:00 = 0),
//                        kept through power cycles: SAFE-OP is refused (0x0025) until a master rewrites it
//   foreign-mapping SLAVE  SLAVE's PDO mapping reset to another drive's default (2 entries each way)
//   refuse SLAVE STATE CODE  SLAVE refuses every request for STATE (pre-op, safe-op, op) with AL status
//                        code CODE (error bit set; CODE 0 accepts again)
//   extra-slave          the spare slave (the simulated robot's: a junction behind the last slave)
//                        powered on: one more device at the end of a chain
//   safe-op SLAVE CODE   SLAVE's application drops it from OP to SAFE-OP with AL status code CODE
//                        (error bit set), e.g. 0x001A synchronisation error; it still exchanges process data
//
// The text is untrusted: every token is checked, nothing is assumed about its length.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "hal/time/clock.hpp"

namespace rescue::drivers {

enum class FaultKind : std::uint8_t {
  cut,
  restore,
  freeze,
  thaw,
  power_off,
  power_on,
  drop,
  corrupt,
  drive_fault,
  power_cycle,
  replace_cable,
  foreign,
  original,
  corrupt_port,
  safe_op,
  half_mapped,
  foreign_mapping,
  refuse,
  extra_slave,
};

struct FaultCommand {
  FaultKind kind{FaultKind::cut};
  std::size_t position{0};  // slave, for the commands that name one
  std::uint32_t value{0};   // count (drop, corrupt, corrupt-port) or error code (drive-fault, safe-op)
  std::uint32_t port{0};    // corrupt-port
  AlState state{AlState::init};  // refuse
  bool ring_cable{false};   // cut, restore, replace-cable: the ring-return cable, not a slave's
};

// The word that names the ring-return cable in place of a slave.
constexpr const char* kRingCableWord = "ring";

// Parses one line (at most `length` characters, stops at the first NUL). Slave names are looked up
// in `segment`. Errors name what was wrong (unknown command, unknown slave, bad number, extra words).
Result<FaultCommand> parse_fault_command(const char* text, std::size_t length, const SimulatedSegment& segment) noexcept;

// Applies a parsed command at segment time `now`.
Status apply_fault_command(const FaultCommand& command, SimulatedSegment& segment, hal::Nanoseconds now) noexcept;

}  // namespace rescue::drivers
