#include "core/session.h"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/testing.h"

namespace mesocap {
namespace {

TEST(Session, JournalSurvivesATornLastLine) {
  const auto root = testing::MakeTempDir() / "s";
  auto s = Session::Create(root, {{"source", "test"}});
  ASSERT_TRUE(s.ok()) << s.status().message();
  for (int i = 1; i <= 3; ++i) {
    ShotRecord r;
    r.index = i;
    r.file = Session::ShotFileName("shot", i, ".jpg");
    ASSERT_TRUE(s->RecordShot(r).ok());
  }
  // A crash while appending the fourth record leaves half a line.
  std::ofstream(root / Session::kJournalName, std::ios::app) << R"({"event":"shot","index":4,"ki)";
  auto reopened = Session::Open(root);
  ASSERT_TRUE(reopened.ok());
  EXPECT_EQ(reopened->shots().size(), 3u);
  EXPECT_EQ(reopened->torn_journal_lines(), 1);
  EXPECT_EQ(reopened->NextIndex("shot"), 4);
  EXPECT_EQ(reopened->manifest().at("source"), "test");
  // The next record after the torn line survives whole.
  ShotRecord r;
  r.index = 4;
  r.file = Session::ShotFileName("shot", 4, ".jpg");
  ASSERT_TRUE(reopened->RecordShot(r).ok());
  auto again = Session::Open(root);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again->shots().size(), 4u);
  EXPECT_EQ(again->torn_journal_lines(), 1);
}

TEST(Session, NextIndexSkipsFilesThatWereNeverJournaled) {
  const auto root = testing::MakeTempDir() / "s";
  auto s = Session::Create(root, {});
  ASSERT_TRUE(s.ok());
  std::filesystem::create_directories(root / "shots");
  std::ofstream(root / Session::ShotFileName("shot", 7, ".jpg")) << "x";
  EXPECT_EQ(s->NextIndex("shot"), 8);
  EXPECT_EQ(s->NextIndex("calib"), 1);
}

TEST(Session, RefusesANonEmptyFolder) {
  const auto root = testing::MakeTempDir();
  std::ofstream(root / "x") << "x";
  auto s = Session::Create(root, {});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("not empty"), std::string::npos);
}

}  // namespace
}  // namespace mesocap
