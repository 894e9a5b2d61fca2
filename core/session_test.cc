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
    r.file = SessionLayout::ShotEntry("shot", i, ".jpg");
    ASSERT_TRUE(s->RecordShot(r).ok());
  }
  // A crash while appending the fourth record leaves half a line.
  std::ofstream(SessionLayout(root).journal(), std::ios::app) << R"({"event":"shot","index":4,"ki)";
  auto reopened = Session::Open(root);
  ASSERT_TRUE(reopened.ok());
  EXPECT_EQ(reopened->shots().size(), 3u);
  EXPECT_EQ(reopened->torn_journal_lines(), 1);
  EXPECT_EQ(reopened->NextIndex("shot"), 4);
  EXPECT_EQ(reopened->manifest().at("source"), "test");
  // The next record after the torn line survives whole.
  ShotRecord r;
  r.index = 4;
  r.file = SessionLayout::ShotEntry("shot", 4, ".jpg");
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
  std::ofstream(root / SessionLayout::ShotEntry("shot", 7, ".jpg")) << "x";
  EXPECT_EQ(s->NextIndex("shot"), 8);
  EXPECT_EQ(s->NextIndex("calib"), 1);
}

TEST(Session, ARejectedShotLeavesTheStagesListButKeepsItsFileAndIndex) {
  const auto root = testing::MakeTempDir() / "s";
  auto s = Session::Create(root, {});
  ASSERT_TRUE(s.ok());
  for (int i = 1; i <= 3; ++i) {
    ShotRecord r;
    r.index = i;
    r.file = SessionLayout::ShotEntry("shot", i, ".jpg");
    ASSERT_TRUE(s->RecordShot(r).ok());
  }
  const std::string second = SessionLayout::ShotEntry("shot", 2, ".jpg");
  ASSERT_TRUE(s->RejectShot(second, "undone in the console").ok());
  EXPECT_FALSE(s->RejectShot(second, "again").ok());  // once only
  EXPECT_FALSE(s->RejectShot(SessionLayout::ShotEntry("shot", 9, ".jpg"), "never taken").ok());
  auto reopened = Session::Open(root);
  ASSERT_TRUE(reopened.ok()) << reopened.status().message();
  ASSERT_EQ(reopened->ShotsOfKind("shot").size(), 2u);
  EXPECT_EQ(reopened->ShotsOfKind("shot")[1].index, 3);
  EXPECT_EQ(reopened->shots().size(), 3u);  // still journaled: capture's recovery must not take it again
  EXPECT_TRUE(reopened->IsRejected(second));
  EXPECT_EQ(reopened->rejected().at(second), "undone in the console");
  EXPECT_EQ(reopened->NextIndex("shot"), 4);
  // A reject record naming a shot no earlier line records is an error naming the line.
  std::ofstream(SessionLayout(root).journal(), std::ios::app)
      << R"({"event":"reject","file":"shots/shot_0042.jpg"})" << "\n";
  auto bad = Session::Open(root);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("line 5"), std::string::npos) << bad.status().message();
}

TEST(Session, RefusesANonEmptyFolder) {
  const auto root = testing::MakeTempDir();
  std::ofstream(root / "x") << "x";
  auto s = Session::Create(root, {});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("not empty"), std::string::npos);
}

void WriteFile(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }

TEST(Session, AManifestThatIsNotAnObjectIsRefusedNamingTheFile) {
  const auto dir = testing::MakeTempDir();
  for (const char* manifest : {"[1, 2]", "\"text\"", "42", "{\"format\": \"mesocap-btf\"}"}) {
    WriteFile(dir / "session.json", manifest);
    auto s = Session::Open(dir);
    ASSERT_FALSE(s.ok()) << manifest;
    EXPECT_NE(s.status().message().find("session.json"), std::string::npos) << s.status().message();
  }
}

TEST(Session, JournalIndicesAndPathsAreValidated) {
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(Session::Create(dir, Json::object()).ok());
  const std::string good = R"({"event":"shot","index":1,"kind":"shot","file":"shots/shot_0001.jpg"})";
  const std::pair<std::string, std::string> bad[] = {
      {R"({"event":"shot","index":2147483647,"kind":"shot","file":"shots/x.jpg"})", "index = 2147483647 is outside [1, 999999]"},
      {R"({"event":"shot","index":0,"kind":"shot","file":"shots/x.jpg"})", "index = 0"},
      {R"({"event":"shot","index":2,"kind":"shot","file":"/etc/passwd"})", "must be a relative path"},
      {R"({"event":"shot","index":2,"kind":"shot","file":"shots/../../x.jpg"})", "must not leave its folder"},
      {R"({"event":"shot","index":2,"kind":"flash","file":"shots/x.jpg"})", "kind 'flash'"},
      {R"({"event":"shot","index":"2","kind":"shot","file":"shots/x.jpg"})", "index must be an integer"},
  };
  for (const auto& [line, fragment] : bad) {
    WriteFile(dir / "journal.jsonl", good + "\n" + line + "\n" + good + "\n");
    auto s = Session::Open(dir);
    ASSERT_FALSE(s.ok()) << line;
    EXPECT_NE(s.status().message().find("journal.jsonl line 2: "), std::string::npos) << s.status().message();
    EXPECT_NE(s.status().message().find(fragment), std::string::npos) << s.status().message();
  }
  WriteFile(dir / "journal.jsonl", good + "\n");
  std::filesystem::create_directories(dir / "shots");
  WriteFile(dir / "shots" / "shot_99999999999.jpg", "");
  WriteFile(dir / "shots" / "shot_-5.jpg", "");
  auto s = Session::Open(dir);
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_EQ(s->NextIndex("shot"), 2) << "names that are not valid indices do not move the next index";
}

TEST(Json, ANumberTooLargeForADoubleIsAnErrorNamingTheFile) {
  // Found by fuzz/fuzz_camera_json: nlohmann throws out_of_range (406), not parse_error.
  const auto dir = testing::MakeTempDir();
  WriteFile(dir / "big.json", "{\"width\": 55555555555555555555555555e55555555555555}");
  auto j = ReadJsonFile(dir / "big.json");
  ASSERT_FALSE(j.ok());
  EXPECT_NE(j.status().message().find("big.json: invalid JSON"), std::string::npos) << j.status().message();
}

}  // namespace
}  // namespace mesocap
