#include "core/base/result.hpp"

namespace rescue {

const char* to_string(Errc code) noexcept {
  switch (code) {
    case Errc::ok: return "ok";
    case Errc::invalid_argument: return "invalid argument";
    case Errc::out_of_range: return "out of range";
    case Errc::capacity_exceeded: return "capacity exceeded";
    case Errc::truncated: return "truncated";
    case Errc::malformed: return "malformed";
    case Errc::checksum: return "checksum mismatch";
    case Errc::version: return "unsupported version";
    case Errc::timeout: return "timeout";
    case Errc::io_error: return "I/O error";
    case Errc::permission_denied: return "permission denied";
    case Errc::not_found: return "not found";
    case Errc::busy: return "busy";
    case Errc::refused: return "refused";
    case Errc::mismatch: return "mismatch";
    case Errc::unsupported: return "unsupported";
  }
  return "unknown error";
}

}  // namespace rescue
