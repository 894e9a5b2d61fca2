#include "capture/simulate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "core/atomic_file.h"
#include "core/session.h"
#include "tests/testing.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

SimulateOptions Small(const fs::path& out, uint64_t seed) {
  SimulateOptions o;
  o.rig.shots = 3;
  o.rig.calib_shots = 2;
  o.rig.seed = seed;
  o.rig.width = 900;
  o.rig.height = 600;
  o.out = out;
  return o;
}

std::vector<std::string> FilesToCompare(const fs::path& root) {
  std::vector<std::string> files = {"truth.json", "journal.jsonl"};
  for (const char* sub : {"shots", "calib"})
    for (const auto& e : fs::directory_iterator(root / sub)) files.push_back(fs::relative(e.path(), root).string());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(Simulate, SameSeedSameBytes) {
  const auto dir = testing::MakeTempDir();
  ASSERT_TRUE(SimulateSession(Small(dir / "a", 5)).ok());
  ASSERT_TRUE(SimulateSession(Small(dir / "b", 5)).ok());
  ASSERT_TRUE(SimulateSession(Small(dir / "c", 6)).ok());
  const auto files = FilesToCompare(dir / "a");
  EXPECT_EQ(files.size(), 7u);
  EXPECT_EQ(files, FilesToCompare(dir / "b"));
  int differing_from_c = 0;
  for (const auto& f : files) {
    EXPECT_EQ(*ReadTextFile(dir / "a" / f), *ReadTextFile(dir / "b" / f)) << f;
    if (f != "journal.jsonl")  // the journal holds the virtual clock and settings: seed-independent
      differing_from_c += *ReadTextFile(dir / "a" / f) != *ReadTextFile(dir / "c" / f);
  }
  EXPECT_EQ(differing_from_c, int(files.size()) - 1);
}

TEST(Simulate, SessionHasJournalManifestAndTruth) {
  const auto dir = testing::MakeTempDir();
  auto report = SimulateSession(Small(dir / "s", 1));
  ASSERT_TRUE(report.ok()) << report.status().message();
  auto session = Session::Open(dir / "s");
  ASSERT_TRUE(session.ok());
  EXPECT_EQ(session->ShotsOfKind("shot").size(), 3u);
  EXPECT_EQ(session->ShotsOfKind("calib").size(), 2u);
  EXPECT_EQ(session->manifest().at("source"), "virtual");
  auto truth = ReadJsonFile(dir / "s" / "truth.json");
  ASSERT_TRUE(truth.ok());
  for (const char* key : {"camera", "boards", "spheres", "grey_cards", "shots", "checkerboard", "calib_shots"})
    EXPECT_TRUE(truth->contains(key)) << key;
  EXPECT_EQ(truth->at("boards").size(), 13u);
  EXPECT_EQ(truth->at("boards")[0].at("tags")[0].at("corners_m").size(), 4u);
  for (const auto& shot : truth->at("shots")) EXPECT_TRUE(fs::exists(dir / "s" / shot.at("file").get<std::string>()));
  // Nothing but the session itself is left beside it.
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(Simulate, BadOptionsAreRefusedWithAReason) {
  const auto dir = testing::MakeTempDir();
  SimulateOptions o = Small(dir / "x", 1);
  o.rig.material = "velvet";
  EXPECT_NE(o.Check().find("unknown material"), std::string::npos);
  o = Small(dir / "x", 1);
  o.rig.width = 10;
  EXPECT_NE(o.Check().find("--width"), std::string::npos);
  o = Small(dir / "x", 1);
  o.rig.shots = 0;
  EXPECT_NE(o.Check().find("--shots"), std::string::npos);
  o = Small(dir, 1);
  std::ofstream(dir / "something") << "x";
  EXPECT_NE(o.Check().find("not empty"), std::string::npos);
  auto r = SimulateSession(o);
  EXPECT_FALSE(r.ok());
}

}  // namespace
}  // namespace mesocap
