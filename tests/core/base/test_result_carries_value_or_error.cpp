#include <gtest/gtest.h>

#include <cstring>

#include "core/base/result.hpp"

namespace rescue {
namespace {

Result<int> parse_digit(char c) {
  if (c < '0' || c > '9') return make_error(Errc::invalid_argument, "not a digit", static_cast<std::uint32_t>(c));
  return c - '0';
}

Status check_both(char a, char b) {
  RESCUE_TRY(parse_digit(a));
  RESCUE_TRY(parse_digit(b));
  return Status::success();
}

TEST(Result, CarriesValue) {
  auto r = parse_digit('7');
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.value(), 7);
}

TEST(Result, CarriesErrorWithDetails) {
  auto r = parse_digit('x');
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().code, Errc::invalid_argument);
  EXPECT_STREQ(r.error().what, "not a digit");
  EXPECT_EQ(r.error().detail0, static_cast<std::uint32_t>('x'));
  EXPECT_EQ(r.value_or(-1), -1);
}

TEST(Result, TryPropagatesFirstError) {
  EXPECT_TRUE(check_both('1', '2').ok());
  const Status s = check_both('1', 'q');
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().detail0, static_cast<std::uint32_t>('q'));
}

TEST(Result, EveryErrcHasAName) {
  for (int c = 0; c <= static_cast<int>(Errc::unsupported); ++c) {
    EXPECT_STRNE(to_string(static_cast<Errc>(c)), "unknown error") << c;
  }
}

}  // namespace
}  // namespace rescue
