// The process report reads the stages' records typed: what a record says shows, and a record that
// is there but malformed is said to be so (file and field), never shown as zeros or left out.
#include <gtest/gtest.h>

#include "app/process.h"
#include "core/atomic_file.h"
#include "core/json.h"
#include "core/session_layout.h"
#include "tests/testing.h"

namespace mesocap::app {
namespace {
namespace fs = std::filesystem;

std::string ReportOf(const SessionLayout& session) {
  EXPECT_TRUE(WriteProcessReport(session.root(), {}).ok());
  auto md = ReadTextFile(session.report_md());
  EXPECT_TRUE(md.ok());
  return md.ok() ? *md : "";
}

TEST(ProcessReport, ShowsWhatTheRecordsSayAndNamesAMalformedField) {
  const SessionLayout session(testing::MakeTempDir());
  fs::create_directories(session.calibration().root);
  ASSERT_TRUE(WriteJsonFile(session.calibration().report(), {{"rejected", {"shot_0007.jpg: no ball highlight"}}}).ok());
  std::string md = ReportOf(session);
  EXPECT_NE(md.find("no ball highlight"), std::string::npos) << md;
  EXPECT_EQ(md.find("Could not be read"), std::string::npos) << md;

  ASSERT_TRUE(WriteJsonFile(session.calibration().report(), {{"rejected", {7}}}).ok());
  md = ReportOf(session);
  EXPECT_NE(md.find("Could not be read"), std::string::npos) << md;
  EXPECT_NE(md.find("rejected[0]"), std::string::npos) << md;

  fs::create_directories(session.synth().root);
  ASSERT_TRUE(WriteJsonFile(session.synth().report(), {{"method", "quilt"}, {"output", {{"width", 512}}}}).ok());
  md = ReportOf(session);
  EXPECT_NE(md.find("output.height"), std::string::npos) << "a missing size is named, not shown as 0:\n" << md;
  ASSERT_TRUE(
      WriteJsonFile(session.synth().report(), {{"method", "quilt"}, {"output", {{"width", 512}, {"height", 384}}}}).ok());
  md = ReportOf(session);
  EXPECT_NE(md.find("quilt to 512x384"), std::string::npos) << md;
}

}  // namespace
}  // namespace mesocap::app
