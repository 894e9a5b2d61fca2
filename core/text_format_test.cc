#include "core/text_format.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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

TEST(Text, ListedLinesStopsAtMostAndCountsTheRest) {
  const auto line = [](int k) { return "item " + std::to_string(k); };
  EXPECT_EQ(ListedLines(std::vector<int>{}, 2, "x.json", line), "");
  EXPECT_EQ(ListedLines(std::vector<int>{1, 2}, 2, "x.json", line), "\n  item 1\n  item 2");
  EXPECT_EQ(ListedLines(std::vector<int>{1, 2, 3, 4, 5}, 2, "x.json", line),
            "\n  item 1\n  item 2\n  ... and 3 more (see x.json)");
}

}  // namespace
}  // namespace mesocap
