#include "formats/lp_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/atomic_file.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

void Touch(const fs::path& p) { std::ofstream(p) << "x"; }

void ExpectError(const StatusOr<std::vector<LpEntry>>& result, const std::string& fragment) {
  ASSERT_FALSE(result.ok()) << "expected an error containing '" << fragment << "'";
  EXPECT_NE(result.status().message().find(fragment), std::string::npos)
      << result.status().message();
}

TEST(LpFile, WriteReadRoundTrip) {
  const fs::path dir = testing::MakeTempDir();
  std::vector<LpEntry> entries;
  for (int i = 0; i < 7; ++i) {
    const fs::path image = dir / ("img " + std::to_string(i) + ".jpg");  // names with spaces
    Touch(image);
    entries.push_back({image, Eigen::Vector3d(0.1 * i, -0.05 * i, 0.9).normalized()});
  }
  const fs::path lp = dir / "lights.lp";
  ASSERT_TRUE(WriteLpFile(lp, entries).ok());
  const StatusOr<std::string> text = ReadTextFile(lp);
  ASSERT_TRUE(text.ok());
  EXPECT_EQ(text->substr(0, 2), "7\n");
  EXPECT_NE(text->find("\nimg 0.jpg 0.000000 -0.000000 1.000000\n"), std::string::npos) << *text;

  const auto read = ReadLpFile(lp);
  ASSERT_TRUE(read.ok()) << read.status().message();
  ASSERT_EQ(read->size(), entries.size());
  for (size_t i = 0; i < entries.size(); ++i) {
    EXPECT_EQ(fs::canonical((*read)[i].image), fs::canonical(entries[i].image));
    EXPECT_LT(((*read)[i].light_dir - entries[i].light_dir).norm(), 1e-6);
  }
}

TEST(LpFile, AcceptsCrlfBlankLinesAndWindowsPaths) {
  const fs::path dir = testing::MakeTempDir();
  Touch(dir / "a.jpg");
  Touch(dir / "b.JPG");
  fs::create_directories(dir / "sub");
  Touch(dir / "sub" / "c.png");
  const fs::path lp = dir / "win.lp";
  ASSERT_TRUE(WriteTextAtomically(lp,
                                  "3\r\n\r\nC:\\captures\\coin\\a.jpg 0.5 0.5 0.707107\r\n"
                                  "  b.JPG\t-0.5 0 0.866 \r\nsub\\c.png 0 0 1\r\n\r\n")
                  .ok());
  const auto read = ReadLpFile(lp);
  ASSERT_TRUE(read.ok()) << read.status().message();
  ASSERT_EQ(read->size(), 3u);
  EXPECT_EQ((*read)[0].image, dir / "a.jpg");
  EXPECT_EQ((*read)[1].image, dir / "b.JPG");
  EXPECT_EQ((*read)[2].image, dir / "sub/c.png");
  EXPECT_DOUBLE_EQ((*read)[1].light_dir.x(), -0.5);
  EXPECT_DOUBLE_EQ((*read)[2].light_dir.z(), 1.0);
}

TEST(LpFile, MissingImageIsNamed) {
  const fs::path dir = testing::MakeTempDir();
  Touch(dir / "a.jpg");
  const fs::path lp = dir / "lights.lp";
  ASSERT_TRUE(WriteTextAtomically(lp, "2\na.jpg 0 0 1\nmissing_07.jpg 0.5 0 0.86\n").ok());
  const auto read = ReadLpFile(lp);
  ExpectError(read, "lights.lp:3: image 'missing_07.jpg' not found");
  EXPECT_NE(read.status().message().find((dir / "missing_07.jpg").string()), std::string::npos);
  // Without the existence check the entries parse.
  const auto lenient = ReadLpFile(lp, /*require_images_exist=*/false);
  ASSERT_TRUE(lenient.ok()) << lenient.status().message();
  EXPECT_EQ((*lenient)[1].image, dir / "missing_07.jpg");
}

TEST(LpFile, MalformedFiles) {
  const fs::path dir = testing::MakeTempDir();
  Touch(dir / "a.jpg");
  const fs::path lp = dir / "bad.lp";
  auto check = [&](const std::string& text, const std::string& fragment) {
    ASSERT_TRUE(WriteTextAtomically(lp, text).ok());
    ExpectError(ReadLpFile(lp), fragment);
    ExpectError(ReadLpFile(lp), lp.string());
  };
  check("", "empty light-position file");
  check("two\na.jpg 0 0 1\n", "first line must be the number of images");
  check("2.5\na.jpg 0 0 1\n", "first line must be the number of images");
  check("2\na.jpg 0 0 1\n", "declares 2 images but the file lists 1");
  check("1\na.jpg 0 0 1\na.jpg 0 0 1\n", "bad.lp:3: more image lines than the 1");
  check("1\na.jpg 0 zero 1\n", "bad.lp:2: light coordinate 'zero' is not a number");
  check("1\n0 0 1\n", "expected 'filename x y z'");
  check("1\na.jpg 0 0 0\n", "light direction is (0, 0, 0)");
  ExpectError(ReadLpFile(dir / "none.lp"), "none.lp: cannot open");
}

}  // namespace
}  // namespace mesocap
