#include "core/text_format.h"

#include <gtest/gtest.h>

namespace mesocap {
namespace {

TEST(Format, LongTextIsNotTruncated) {
  const std::string long_path(2000, 'p');
  const std::string text = Format("%s: %d of %.2f", long_path.c_str(), 3, 4.5);
  EXPECT_EQ(text.size(), 2000u + 11u);
  EXPECT_EQ(text.substr(2000), ": 3 of 4.50");
}

TEST(Format, PrintfConversionsAsBefore) {
  EXPECT_EQ(Format("%5.1f|%-4s|%03d|%.3g|%zu", 2.25, "ab", 7, 1234.5, size_t(9)), "  2.2|ab  |007|1.23e+03|9");
}

TEST(Text, LowerAndTrim) {
  EXPECT_EQ(Lower(".JPG Canon EOS"), ".jpg canon eos");
  EXPECT_EQ(Trim("  \tCanon EOS R5 \r\n"), "Canon EOS R5");
  EXPECT_EQ(Trim(" \t\n"), "");
  EXPECT_EQ(Trim(""), "");
}

}  // namespace
}  // namespace mesocap
