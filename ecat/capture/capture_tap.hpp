// Wires a CaptureWriter to the master's DatagramLink, so every frame the master sends and every
// frame it receives (late ones included) lands in the capture with the NIC clock's time:
//
//   static CaptureWriter capture;                                 // before init complete
//   CaptureWriterOptions options;
//   options.timestamp_offset = unix_time_offset(nic.clock());    // Wireshark shows wall-clock time
//   RESCUE_TRY(capture.open(path, options));                      // `run --capture FILE`
//   master.set_tap(capture_tap, &capture);                        // or link.set_tap(...)
//   ... cycles ...
//   capture.stats(): frames_written, write_errors (report at exit), then capture.close()
//
// record() never fails the cycle: a refused write is counted in stats() and the frame is lost.
#pragma once

#include "ecat/capture/capture_writer.hpp"
#include "ecat/link/datagram_link.hpp"

namespace rescue::ecat {

// A FrameTapFn: `writer` is the CaptureWriter given to set_tap().
inline void capture_tap(void* writer, ConstByteSpan frame, hal::Nanoseconds time, TapDirection direction) noexcept {
  static_cast<CaptureWriter*>(writer)->record(
      frame, time, direction == TapDirection::outbound ? FrameDirection::outbound : FrameDirection::inbound);
}

}  // namespace rescue::ecat
