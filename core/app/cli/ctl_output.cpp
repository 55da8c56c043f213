#include "core/app/cli/ctl_output.hpp"

#include <cinttypes>
#include <cstdio>
#include <cstring>

namespace rescue::app {
namespace {

bool printable(unsigned c) noexcept { return c >= 0x20 && c < 0x7F; }

void json_char(unsigned c) noexcept {
  if (c == '"' || c == '\\') {
    (void)std::printf("\\%c", c);
  } else if (printable(c)) {
    (void)std::putchar(static_cast<int>(c));
  } else {
    (void)std::printf("\\u%04x", c);
  }
}

void text_char(unsigned c) noexcept {
  if (c == '\\') {
    (void)std::fputs(R"(\\)", stdout);
  } else if (printable(c)) {
    (void)std::putchar(static_cast<int>(c));
  } else {
    (void)std::printf("\\x%02x", c);
  }
}

}  // namespace

CtlOutput& ctl_output() noexcept {
  static CtlOutput output;
  return output;
}

void print_json_string(const char* s) noexcept {
  (void)std::putchar('"');
  for (; *s != '\0'; ++s) json_char(static_cast<unsigned char>(*s));
  (void)std::putchar('"');
}

void print_json_bytes(const std::uint8_t* data, std::size_t n) noexcept {
  (void)std::putchar('"');
  for (std::size_t i = 0; i < n; ++i) json_char(data[i]);
  (void)std::putchar('"');
}

void print_text_string(const char* s) noexcept {
  for (; *s != '\0'; ++s) text_char(static_cast<unsigned char>(*s));
}

void print_text_bytes(const std::uint8_t* data, std::size_t n) noexcept {
  for (std::size_t i = 0; i < n; ++i) text_char(data[i]);
}

void begin_json(bool ok) noexcept {
  (void)std::printf("{\"command\":");
  print_json_string(ctl_output().verb);
  (void)std::printf(",\"ok\":%s", ok ? "true" : "false");
}

void end_json() noexcept { (void)std::printf("}\n"); }

void print_age_json(const protocol::FiguresAge& age) noexcept {
  (void)std::printf(",\"age_ms\":%" PRIu32 ",\"stale\":%s", age.age_ms, age.stale ? "true" : "false");
}

void print_age_text(const protocol::FiguresAge& age) noexcept {
  if (!age.stale) return;
  (void)std::printf("STALE: the EtherCAT handler has completed no period for %" PRIu32
                    " ms; these figures are that old\n",
                    age.age_ms);
}

const char* to_string(CtlExit code) noexcept {
  switch (code) {
    case CtlExit::ok:
      return "ok";
    case CtlExit::refused:
      return "refused";
    case CtlExit::usage:
      return "usage";
    case CtlExit::unreachable:
      return "unreachable";
    case CtlExit::local:
      return "local";
    case CtlExit::bad_answer:
      return "bad_answer";
  }
  return "?";
}

int ctl_error(CtlExit code, const char* text) noexcept {
  (void)std::fprintf(stderr, "rescue-motion ctl: %s\n", text);
  if (ctl_output().json) {
    begin_json(false);
    (void)std::printf(R"(,"error":)");
    print_json_string(text);
    (void)std::printf(R"(,"exit":"%s")", to_string(code));
    end_json();
  }
  return static_cast<int>(code);
}

int ctl_unexpected_answer(const protocol::Message& answer) noexcept {
  char text[96];
  (void)std::snprintf(text, sizeof text, "%s: unexpected answer type 0x%02x", ctl_output().verb,
                      static_cast<unsigned>(answer.header.type));
  return ctl_error(CtlExit::bad_answer, text);
}

CtlExit exit_of(Errc code) noexcept {
  switch (code) {
    case Errc::invalid_argument:
    case Errc::out_of_range:
      return CtlExit::usage;
    case Errc::timeout:
    case Errc::io_error:
      return CtlExit::unreachable;
    case Errc::refused:
      return CtlExit::refused;
    default:
      return CtlExit::local;
  }
}

}  // namespace rescue::app
