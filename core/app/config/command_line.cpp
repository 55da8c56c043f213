#include "core/app/config/command_line.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace rescue::app {
namespace {

const OptionSpec* find_option(const CommandSpec& spec, const char* name, std::size_t name_len) noexcept {
  for (const OptionSpec& opt : spec.options) {
    if (std::strlen(opt.name) == name_len && std::strncmp(opt.name, name, name_len) == 0) return &opt;
  }
  return nullptr;
}

}  // namespace

const char* ParsedArgs::value(const char* name) const noexcept {
  for (const Entry& e : options_) {
    if (std::strcmp(e.name, name) == 0) return e.value;  // each option at most once (parse_args)
  }
  return nullptr;
}

bool ParsedArgs::has(const char* name) const noexcept {
  return std::any_of(options_.begin(), options_.end(), [name](const Entry& e) { return std::strcmp(e.name, name) == 0; });
}

namespace {

// The range goes in the details when it is whole and fits (fail() prints it); detail1 = max + 1 so
// that 0 means "no range known".
Error range_error(const char* what, double min, double max) noexcept {
  const bool fits = min >= 0.0 && max < 4294967295.0 && min == static_cast<double>(static_cast<std::uint32_t>(min)) &&
                    max == static_cast<double>(static_cast<std::uint32_t>(max));
  if (!fits) return make_error(Errc::out_of_range, what);
  return make_error(Errc::out_of_range, what, static_cast<std::uint32_t>(min), static_cast<std::uint32_t>(max) + 1U);
}

}  // namespace

Result<std::int64_t> ParsedArgs::integer(const char* name, std::int64_t fallback, std::int64_t min,
                                         std::int64_t max) const noexcept {
  const char* text = value(name);
  if (text == nullptr) return fallback;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text, &end, 0);
  if (errno != 0 || end == text || *end != '\0') return make_error(Errc::invalid_argument, "not an integer");
  if (v < min || v > max) return range_error("integer out of range", static_cast<double>(min), static_cast<double>(max));
  return static_cast<std::int64_t>(v);
}

Result<double> ParsedArgs::number(const char* name, double fallback, double min, double max) const noexcept {
  const char* text = value(name);
  if (text == nullptr) return fallback;
  // Decimal only: strtod would also take hexadecimal ("0x10" = 16), "inf" and "nan".
  for (const char* c = text; *c != '\0'; ++c) {
    if (std::strchr("0123456789.+-eE", *c) == nullptr) return make_error(Errc::invalid_argument, "not a decimal number");
  }
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text, &end);
  if (errno != 0 || end == text || *end != '\0') return make_error(Errc::invalid_argument, "not a decimal number");
  if (!(v >= min && v <= max)) return range_error("number out of range", min, max);
  return v;
}

Result<ParsedArgs> parse_args(const CommandSpec& spec, int argc, const char* const* argv) noexcept {
  ParsedArgs parsed;
  bool options_ended = false;
  for (int i = 0; i < argc; ++i) {
    const char* arg = argv[i];
    const auto index = static_cast<std::uint32_t>(i);
    if (!options_ended && (std::strcmp(arg, "--help") == 0 || std::strcmp(arg, "-h") == 0)) {
      parsed.help_ = true;
      continue;
    }
    if (!options_ended && std::strcmp(arg, "--") == 0) {
      options_ended = true;
      continue;
    }
    if (!options_ended && std::strncmp(arg, "--", 2) == 0) {
      const char* name = arg + 2;
      const char* eq = std::strchr(name, '=');
      const std::size_t name_len = eq != nullptr ? static_cast<std::size_t>(eq - name) : std::strlen(name);
      const OptionSpec* opt = find_option(spec, name, name_len);
      if (opt == nullptr) return make_error(Errc::invalid_argument, "unknown option", index);
      const char* value = nullptr;
      if (opt->value_name != nullptr) {
        if (eq != nullptr) {
          value = eq + 1;
        } else if (i + 1 < argc) {
          value = argv[++i];
        } else {
          return make_error(Errc::invalid_argument, "option needs a value", index);
        }
      } else if (eq != nullptr) {
        return make_error(Errc::invalid_argument, "option takes no value", index);
      }
      // Each option once, as each key of the configuration file: a repeated one is a mistake to
      // name, not a value to pick silently.
      if (parsed.has(opt->name)) return make_error(Errc::invalid_argument, "option given twice (each option once)", index);
      if (!parsed.options_.push_back(ParsedArgs::Entry{opt->name, value})) {
        return make_error(Errc::capacity_exceeded, "too many options", index);
      }
      continue;
    }
    if (!options_ended && arg[0] == '-' && arg[1] != '-' && arg[1] != '\0' && arg[2] == '\0') {
      const OptionSpec* opt = std::find_if(spec.options.begin(), spec.options.end(),
                                           [arg](const OptionSpec& o) { return o.short_name != '\0' && o.short_name == arg[1]; });
      if (opt != spec.options.end() && opt->value_name == nullptr) {  // one-letter flags only
        if (parsed.has(opt->name)) return make_error(Errc::invalid_argument, "option given twice (each option once)", index);
        if (!parsed.options_.push_back(ParsedArgs::Entry{opt->name, nullptr})) {
          return make_error(Errc::capacity_exceeded, "too many options", index);
        }
        continue;
      }
    }
    if (!options_ended && arg[0] == '-' && arg[1] != '\0') {
      return make_error(Errc::invalid_argument, "unknown option", index);
    }
    if (parsed.positionals_.size() >= spec.max_positionals || !parsed.positionals_.push_back(arg)) {
      return make_error(Errc::invalid_argument, "unexpected argument", index);
    }
  }
  if (!parsed.help_ && parsed.positionals_.size() < spec.min_positionals) {
    return make_error(Errc::invalid_argument, "missing argument",
                      static_cast<std::uint32_t>(parsed.positionals_.size()));
  }
  return parsed;
}

namespace {

constexpr std::size_t kLeftColumn = 2;   // "  --option VALUE"
constexpr std::size_t kTextColumn = 31;  // after the option's 28 columns and a space

void print_spaces(std::FILE* out, std::size_t n) noexcept {
  for (std::size_t i = 0; i < n; ++i) (void)std::fputc(' ', out);
}

// Writes the words of [text, end) from column `at`, breaking before a word that would pass
// kHelpColumns; a continuation starts at `indent`. A word wider than a line stays whole. Ends the line.
void print_words(std::FILE* out, const char* text, const char* end, std::size_t at, std::size_t indent) noexcept {
  bool line_empty = true;
  while (text < end) {
    while (text < end && *text == ' ') ++text;
    const char* word_end = text;
    while (word_end < end && *word_end != ' ') ++word_end;
    if (word_end == text) break;
    const auto length = static_cast<std::size_t>(word_end - text);
    if (!line_empty && at + 1 + length > kHelpColumns) {
      (void)std::fputc('\n', out);
      print_spaces(out, indent);
      at = indent;
      line_empty = true;
    }
    if (!line_empty) {
      (void)std::fputc(' ', out);
      ++at;
    }
    (void)std::fwrite(text, 1, length, out);
    at += length;
    line_empty = false;
    text = word_end;
  }
  (void)std::fputc('\n', out);
}

// One line of help text (no newline inside).
void print_help_line(std::FILE* out, const char* line, const char* end) noexcept {
  if (static_cast<std::size_t>(end - line) <= kHelpColumns) {  // as written: a table keeps its spacing
    (void)std::fwrite(line, 1, static_cast<std::size_t>(end - line), out);
    (void)std::fputc('\n', out);
    return;
  }
  const char* text = line;
  while (text < end && *text == ' ') ++text;
  auto indent = static_cast<std::size_t>(text - line);
  // The description column: after the first run of two or more spaces that follows a word.
  const char* column = text;
  while (column < end && !(column[0] == ' ' && column + 1 < end && column[1] == ' ')) ++column;
  const char* description = column;
  while (description < end && *description == ' ') ++description;
  const auto description_at = static_cast<std::size_t>(description - line);
  if (column < end && description < end && description_at < kHelpColumns / 2) {
    (void)std::fwrite(line, 1, description_at, out);  // the name and its spaces, as written
    indent = description_at;
    text = description;
  } else {
    print_spaces(out, indent);
  }
  print_words(out, text, end, indent, indent);
}

}  // namespace

void print_help_row(std::FILE* out, const char* left, const char* text) noexcept {
  const std::size_t width = std::strlen(left);
  print_spaces(out, kLeftColumn);
  (void)std::fputs(left, out);
  if (kLeftColumn + width + 1 > kTextColumn) {
    (void)std::fputc('\n', out);
    print_spaces(out, kTextColumn);
  } else {
    print_spaces(out, kTextColumn - kLeftColumn - width);
  }
  print_words(out, text, text + std::strlen(text), kTextColumn, kTextColumn);
}

void print_help_text(std::FILE* out, const char* text) noexcept {
  for (const char* line = text;;) {
    const char* end = std::strchr(line, '\n');
    if (end == nullptr) end = line + std::strlen(line);
    print_help_line(out, line, end);
    if (*end == '\0') return;
    line = end + 1;
  }
}

void print_command_help(std::FILE* out, const CommandSpec& spec) noexcept {
  std::fprintf(out, "usage: rescue-motion %s\n\n", spec.usage);
  print_help_text(out, spec.summary);
  if (spec.details[0] != '\0') {
    (void)std::fputc('\n', out);
    print_help_text(out, spec.details);
  }
  std::fprintf(out, "\noptions:\n");
  for (const OptionSpec& opt : spec.options) {
    char left[64];
    if (opt.value_name != nullptr) {
      (void)std::snprintf(left, sizeof left, "--%s %s", opt.name, opt.value_name);  // truncation only narrows the column
    } else {
      if (opt.short_name != '\0') {
        (void)std::snprintf(left, sizeof left, "-%c, --%s", opt.short_name, opt.name);
      } else {
        (void)std::snprintf(left, sizeof left, "--%s", opt.name);
      }
    }
    print_help_row(out, left, opt.help);
  }
  print_help_row(out, "-h, --help", "show this help and exit");
}

int fail(const char* command, const char* what, const Error& error) noexcept {
  if (error.code == Errc::out_of_range && error.detail1 != 0) {
    std::fprintf(stderr, "rescue-motion %s: %s: %s: allowed %u to %u\n", command, what, error.what, error.detail0,
                 error.detail1 - 1U);
    return 1;
  }
  std::fprintf(stderr, "rescue-motion %s: %s: %s (%s)\n", command, what, error.what, to_string(error.code));
  return 1;
}

int fail(const char* command, const char* message) noexcept {
  std::fprintf(stderr, "rescue-motion %s: %s\n", command, message);
  return 1;
}

}  // namespace rescue::app
