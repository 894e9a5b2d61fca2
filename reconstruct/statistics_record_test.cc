// The statistics record the shards of a sharded reconstruction share: a BTF made from it
// reconstructs exactly the bytes of one made from the slices, and a broken record is an error
// naming the file.
#include "reconstruct/statistics_record.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "core/atomic_file.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/json.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

// Three boards of noisy 16x16 slices with lights at two elevations (a Delaunay hull to blend in).
fs::path WriteSlices(const fs::path& dir) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.1f, 0.9f);
  Json slices = Json::array();
  for (const auto& [board, theta_o] : {std::pair{1, 3.0}, {2, 35.0}, {3, 50.0}})
    for (int k = 0; k < 8; ++k) {
      Image slice(16, 16, 3);
      for (size_t i = 0; i < slice.size(); ++i) slice.data()[i] = u(rng) * (k % 2 ? 0.5f : 1.0f);
      const std::string file = "b" + std::to_string(board) + "_" + std::to_string(k) + ".exr";
      EXPECT_TRUE(WriteImage(dir / file, slice, {.format = PixelFormat::kHalf}).ok());
      slices.push_back({{"file", file}, {"board", board}, {"theta_i_deg", k % 2 ? 60 : 25},
                        {"phi_i_deg", 45.0 * k}, {"theta_o_deg", theta_o}, {"phi_o_deg", 90.0 * board}});
    }
  EXPECT_TRUE(WriteJsonFile(dir / "index.json", {{"format", "mesocap-slices"}, {"slices", slices}}).ok());
  return dir / "index.json";
}

SliceSetOptions Options() {
  SliceSetOptions options;
  options.size = 16;
  return options;
}

bool SameBytes(const Image& a, const Image& b) {
  return a.width() == b.width() && a.height() == b.height() && a.channels() == b.channels() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(StatisticsRecord, ABtfFromTheRecordReconstructsTheSameBytes) {
  const fs::path dir = testing::MakeTempDir();
  const fs::path index = WriteSlices(dir);
  SliceSetReport direct_report;
  auto direct = LoadStatisticalBtf(index, Options(), &direct_report);
  ASSERT_TRUE(direct.ok()) << direct.status().message();

  StatisticsRecord record;
  auto inputs = LoadStatisticalBtfInputs(index, Options(), &record.report);
  ASSERT_TRUE(inputs.ok()) << inputs.status().message();
  record.inputs = std::move(*inputs);
  ASSERT_TRUE(WriteStatisticsRecord(dir / "statistics.bin", record).ok());
  auto read = ReadStatisticsRecord(dir / "statistics.bin", Options().btf);
  ASSERT_TRUE(read.ok()) << read.status().message();
  EXPECT_EQ(read->report.views, direct_report.views);
  EXPECT_EQ(read->report.top_board, direct_report.top_board);
  EXPECT_EQ(read->report.slices_used, direct_report.slices_used);
  EXPECT_EQ(read->report.skipped, direct_report.skipped);
  auto from_record = CreateStatisticalBtf(std::move(read->inputs));
  ASSERT_TRUE(from_record.ok()) << from_record.status().message();
  EXPECT_EQ(from_record->white_lobe().ToJson(), direct->white_lobe().ToJson());
  EXPECT_EQ(from_record->mean_model_check().ToJson(), direct->mean_model_check().ToJson());
  EXPECT_EQ(from_record->symmetry_check().ToJson(), direct->symmetry_check().ToJson());
  for (const auto& [ti, pi, to, po] : {std::array{0.0, 0.0, 0.0, 0.0}, {30.0, 45.0, 30.0, 200.0}, {75.0, 300.0, 60.0, 10.0}}) {
    const Eigen::Vector3d light = DirectionFromAnglesDeg(ti, pi), view = DirectionFromAnglesDeg(to, po);
    EXPECT_TRUE(SameBytes(from_record->Reconstruct(light, view), direct->Reconstruct(light, view)))
        << ti << "," << pi << "," << to << "," << po;
  }
}

TEST(StatisticsRecord, ABrokenRecordIsAnErrorNamingTheFile) {
  const fs::path dir = testing::MakeTempDir();
  StatisticsRecord record;
  auto inputs = LoadStatisticalBtfInputs(WriteSlices(dir), Options(), &record.report);
  ASSERT_TRUE(inputs.ok());
  record.inputs = std::move(*inputs);
  const fs::path file = dir / "statistics.bin";
  ASSERT_TRUE(WriteStatisticsRecord(file, record).ok());
  auto bytes = ReadTextFile(file);
  ASSERT_TRUE(bytes.ok());
  for (const size_t keep : {size_t(10), bytes->size() / 2, bytes->size() - 1}) {
    ASSERT_TRUE(WriteTextAtomically(file, bytes->substr(0, keep)).ok());
    auto read = ReadStatisticsRecord(file, Options().btf);
    ASSERT_FALSE(read.ok()) << keep;
    EXPECT_NE(read.status().message().find(file.string()), std::string::npos) << read.status().message();
  }
  ASSERT_TRUE(WriteTextAtomically(file, *bytes + "x").ok());
  EXPECT_FALSE(ReadStatisticsRecord(file, Options().btf).ok());
  ASSERT_TRUE(WriteTextAtomically(file, "{\"format\": \"json\"}\n").ok());
  auto foreign = ReadStatisticsRecord(file, Options().btf);
  ASSERT_FALSE(foreign.ok());
  EXPECT_NE(foreign.status().message().find("not a mesocap-statistics 1 record"), std::string::npos);
}

}  // namespace
}  // namespace mesocap
