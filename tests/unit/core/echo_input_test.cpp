#include "fleetnav/core/echo_input.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace fleetnav {
namespace {

TEST(EchoInputTest, ShortTextIsRepeatedWhole) {
  EXPECT_EQ(EchoInput("barn-2"), "barn-2");
  EXPECT_EQ(EchoInput(std::string(128, 'x')), std::string(128, 'x'));
}

TEST(EchoInputTest, LongTextIsCutWithinTheBudgetAndSaysItsSize) {
  const std::string echoed = EchoInput(std::string(100'000, 'j'));
  EXPECT_LE(echoed.size(), kMaxEchoedInputBytes + 8);  // "…" is three bytes
  EXPECT_THAT(echoed, ::testing::EndsWith("(100000 bytes)"));
  EXPECT_THAT(echoed, ::testing::StartsWith("jjjj"));
}

TEST(EchoInputTest, TheCutNeverSplitsAUtf8Character) {
  std::string text = "a";  // then "ä", two bytes each, starting at odd offsets
  for (int i = 0; i < 100; ++i) text += "\xc3\xa4";
  const std::string echoed = EchoInput(text);
  const size_t cut = echoed.find("\xe2\x80\xa6");  // "…"
  ASSERT_NE(cut, std::string::npos);
  EXPECT_EQ(cut % 2, 1u);
}

}  // namespace
}  // namespace fleetnav
