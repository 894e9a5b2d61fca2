// Catches a forgotten stage-version bump (core/stage_versions.h): a small run of a stage's core
// computation, its output rounded so that the digest does not vary across CPUs (the last bits of
// a floating-point sum may), digested and compared with the digest recorded here for the stage's
// current version. When the output changes on purpose, bump the stage's version and record the
// new digest; a changed digest under an unchanged version fails.
#include "core/stage_versions.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/content_hash.h"
#include "core/directions.h"
#include "core/provenance.h"
#include "reconstruct/ptm.h"

namespace mesocap {
namespace {

struct Recorded {
  int version;
  const char* digest;
};

// The values rounded to 1e-2, in order. A value within 1e-4 of a rounding boundary counts as
// "near" instead: CPUs (fit-ptm has AVX2 and baseline clones) differ by about 1e-7, so every CPU
// rounds each value the same way or calls it near.
std::string RoundedDigest(const Image& image) {
  ContentHasher h;
  for (size_t i = 0; i < image.size(); ++i) {
    const double scaled = double(image.data()[i]) * 100.0;
    const double fraction = scaled - std::floor(scaled);
    h.Add(std::abs(fraction - 0.5) < 0.01 ? std::string("near,") : std::to_string(std::lround(scaled)) + ",");
  }
  return h.Hex();
}

void ExpectRecorded(const std::string& stage, const Recorded& recorded, const std::string& digest) {
  ASSERT_EQ(StageVersion(stage), recorded.version)
      << stage << "'s version changed: record its new output digest here (" << digest << ")";
  EXPECT_EQ(digest, recorded.digest) << stage << "'s output changed under version " << recorded.version
                                     << ": bump its version in core/stage_versions.cc, then record " << digest;
}

// fit-ptm: a least-squares PTM of 16 synthetic 8x8 photographs (smooth shading of a bumpy,
// coloured surface under the lights the tests' virtual-rig PTMs use).
TEST(StageVersions, FitPtmOutputMatchesItsVersion) {
  std::vector<Image> photos;
  std::vector<Eigen::Vector3d> lights;
  for (int k = 0; k < 16; ++k) {
    lights.push_back(DirectionFromAnglesDeg(k < 8 ? 30 : 55, 45.0 * (k % 8) + (k < 8 ? 0 : 22.5)));
    Image photo(8, 8, 3);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        const Eigen::Vector3d n = Eigen::Vector3d(0.3 * std::sin(x), 0.3 * std::cos(y), 1).normalized();
        const double shade = std::max(0.0, n.dot(lights.back()));
        for (int c = 0; c < 3; ++c) photo.at(x, y, c) = float((0.3 + 0.1 * c + 0.05 * ((x + y) % 3)) * shade);
      }
    photos.push_back(std::move(photo));
  }
  PtmFitOptions fit;
  fit.format = PtmFormat::kRgb;
  auto ptm = FitPtm(photos, lights, fit);
  ASSERT_TRUE(ptm.ok()) << ptm.status().message();
  ExpectRecorded("fit-ptm", {1, "d63cc51ae3bd1e071f50012c3b737797"}, RoundedDigest(ptm->coefficients));
}

TEST(StageVersions, EveryStageHasAVersionAndProvenanceNamesThem) {
  for (const char* stage : {"calibrate", "resample", "fit-ptm", "reconstruct", "synth", "export", "decorate"})
    EXPECT_GE(StageVersion(stage), 1) << stage;
  EXPECT_EQ(StageVersion("no-such-stage"), 0);
  EXPECT_EQ(StageVersions().size(), 7u);
  EXPECT_STRNE(SourceRevision(), "");
}

}  // namespace
}  // namespace mesocap
