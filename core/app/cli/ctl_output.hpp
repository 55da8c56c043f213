// What every ctl verb prints with, and the exit statuses a script can rely on (docs/operator.md
// "Exit status", the man page): one status per class of outcome, the same for every verb; every
// string that came from the wire escaped, in text and in JSON (issue 35 item 4: a robot's text must
// neither drive the terminal nor end a JSON string early).
#pragma once

#include <cstdint>

#include "core/app/links/protocol_messages.hpp"
#include "core/base/result.hpp"

namespace rescue::app {

enum class CtlExit : int {
  ok = 0,           // the robot accepted the command or answered the query
  refused = 1,      // the robot (or the drive, for an SDO) answered and refused, with its reason
  usage = 2,        // the command line is wrong: unknown verb or option, a bad or missing argument
  unreachable = 3,  // no authentic answer in time (not running, wrong port or key), or another robot id
  local = 4,        // this station cannot ask: the key or configuration file is unusable, no crypto
  bad_answer = 5,   // an authentic answer that does not fit the request
};

// This invocation's output settings (one client process).
struct CtlOutput {
  bool json{false};             // --json: one object per answer, on one line
  const char* verb{"ctl"};      // the verb, for the envelope and ctl's own errors
  const char* format{nullptr};  // graph --format
};
CtlOutput& ctl_output() noexcept;

// `s` as a JSON string: quotes and backslashes escaped, every byte outside printable ASCII as \u00XX.
void print_json_string(const char* s) noexcept;
void print_json_bytes(const std::uint8_t* data, std::size_t n) noexcept;
// `s` for a terminal: printable ASCII as it is, every other byte as \xNN (a backslash as \\).
void print_text_string(const char* s) noexcept;
void print_text_bytes(const std::uint8_t* data, std::size_t n) noexcept;

// The envelope every JSON answer opens with: {"command":VERB,"ok":true|false — the caller adds its
// members (each after a comma) and closes it with end_json().
void begin_json(bool ok) noexcept;
void end_json() noexcept;
// The figures' age (protocol::FiguresAge): JSON members `,"age_ms":N,"stale":B`, or a text line
// when they are stale.
void print_age_json(const protocol::FiguresAge& age) noexcept;
void print_age_text(const protocol::FiguresAge& age) noexcept;

// ctl's own error (before or instead of an answer): one line on stderr, and with --json one object
// on stdout, {"command":VERB,"ok":false,"error":TEXT,"exit":CLASS}. Returns `code` as the exit status.
int ctl_error(CtlExit code, const char* text) noexcept;
// An authentic answer of another type than the request asks for: exit bad_answer.
int ctl_unexpected_answer(const protocol::Message& answer) noexcept;
// The class of an error from building a request (bad arguments: usage; the exchange it needed:
// unreachable; the robot's refusal: refused).
CtlExit exit_of(Errc code) noexcept;
const char* to_string(CtlExit code) noexcept;

}  // namespace rescue::app
