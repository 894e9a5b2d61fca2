#include "app/btf_method_args.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/json.h"
#include "core/session.h"
#include "tests/testing.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

fs::path SessionWithManifest(const Json& manifest) {
  const fs::path dir = testing::MakeTempDir();
  EXPECT_TRUE(WriteJsonFile(SessionLayout(dir).manifest(), manifest).ok());
  return dir;
}

TEST(BtfMethodArgs, TheImagesACaptureWasGuidedByBindTheReconstruction) {
  const fs::path session = SessionWithManifest({{"format", "mesocap-session"}, {"mirror_images", {"half_turn", "mirror_x"}}});
  BtfMethodArgs args;
  EXPECT_EQ(args.TakeSessionMirrorImages(session), "half_turn, mirror_x");
  StatisticalBtfOptions btf;
  ASSERT_TRUE(args.ApplyTo(&btf));
  EXPECT_EQ(btf.mirror_images_allowed, MirrorImagesNamed({"mirror_x", "half_turn"}));
  EXPECT_EQ(args.ToJson().at("mirror_images"), Json::array({"half_turn", "mirror_x"}));
}

TEST(BtfMethodArgs, TheCommandLineOrNoRecordLeavesTheImagesAsTheyWere) {
  const fs::path session = SessionWithManifest({{"mirror_images", {"half_turn"}}});
  BtfMethodArgs named;
  named.mirror_images = {"quarter_turn"};
  EXPECT_EQ(named.TakeSessionMirrorImages(session), "");
  EXPECT_EQ(named.mirror_images, std::vector<std::string>{"quarter_turn"});
  BtfMethodArgs off;
  off.no_mirror_symmetry = true;
  EXPECT_EQ(off.TakeSessionMirrorImages(session), "");
  EXPECT_TRUE(off.mirror_images.empty());
  // No manifest, none recorded, or a record that is not a list of known names: any image the check finds.
  for (const fs::path& other : {testing::MakeTempDir(), SessionWithManifest({{"format", "mesocap-session"}}),
                                SessionWithManifest({{"mirror_images", "half_turn"}}),
                                SessionWithManifest({{"mirror_images", {"spin", 3}}})}) {
    BtfMethodArgs args;
    EXPECT_EQ(args.TakeSessionMirrorImages(other), "") << other;
    StatisticalBtfOptions btf;
    ASSERT_TRUE(args.ApplyTo(&btf));
    EXPECT_EQ(btf.mirror_images_allowed, kEveryMirrorImage);
  }
  fs::path unreadable = SessionWithManifest({});
  std::ofstream(SessionLayout(unreadable).manifest()) << "{ not json";
  BtfMethodArgs args;
  EXPECT_EQ(args.TakeSessionMirrorImages(unreadable), "");
}

}  // namespace
}  // namespace mesocap::app
