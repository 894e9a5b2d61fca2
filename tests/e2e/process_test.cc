// mesocap process and export through the real CLI on a small rendered session: every stage runs,
// a second run skips them all, a changed option or output reruns only what depends on it, a
// killed run resumes at its stage with nothing half-written in view, and the exports read back
// as what the stages wrote.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <csignal>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include <sys/wait.h>
#include <unistd.h>

#include "core/atomic_file.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/slice_index.h"
#include "core/stage_cache.h"
#include "formats/lp_file.h"
#include "formats/ptm_file.h"
#include "reconstruct/slice_set.h"
#include "reconstruct/white_lobe.h"
#include "mesh/mesh_shapes.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

// Small enough to process in seconds: 10 shots of 1500 x 1000, slices of 32 texels.
// The options of every run, then `extra`; the BTF's grid and size unless `extra` names them.
std::string Options(const fs::path& session, const std::string& extra = "") {
  std::string options = " --slice-size 32 --no-progress";
  if (extra.find("--camera") == std::string::npos) options += " --camera " + (session / "truth.json").string();
  if (extra.find("--btf-grid") == std::string::npos) options += " --btf-grid coarse";
  if (extra.find("--btf-size") == std::string::npos) options += " --btf-size 32";
  return options + extra;
}

class ProcessTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    rendered_ = new fs::path(testing::MakeTempDir() / "rendered");
    std::string out;
    ASSERT_EQ(testing::RunMesocap("simulate --out " + rendered_->string() +
                                      " --shots 10 --calib-shots 0 --width 1500 --height 1000 --no-progress",
                                  &out),
              0)
        << out;
  }
  static void TearDownTestSuite() { delete rendered_; }

  // A fresh copy of the rendered session for one test.
  fs::path FreshSession() {
    const fs::path session = testing::MakeTempDir() / "session";
    fs::copy(*rendered_, session, fs::copy_options::recursive);
    return session;
  }

  // Runs `process` and returns each stage's status from the summary table ("ran", "skipped").
  static std::map<std::string, std::string> Process(const fs::path& session, const std::string& extra = "") {
    std::string out;
    const int code = testing::RunMesocap("process " + session.string() + Options(session, extra), &out);
    EXPECT_EQ(code, 0) << out;
    std::map<std::string, std::string> status;
    for (const char* stage : {"calibrate", "resample", "fit-ptm", "reconstruct", "synth", "export", "decorate"}) {
      const size_t at = out.find("\n" + std::string(stage) + " ");
      if (at == std::string::npos) continue;
      const size_t start = out.find_first_not_of(' ', at + 1 + std::string(stage).size());
      status[stage] = out.substr(start, out.find(' ', start) - start);
    }
    return status;
  }

  static fs::path* rendered_;
};
fs::path* ProcessTest::rendered_ = nullptr;

using Statuses = std::map<std::string, std::string>;
const Statuses kAllRan = {{"calibrate", "ran"}, {"resample", "ran"}, {"fit-ptm", "ran"}, {"reconstruct", "ran"}, {"export", "ran"}};

TEST_F(ProcessTest, RunsEveryStageOnceThenOnlyWhatAChangeAffects) {
  const fs::path s = FreshSession();
  EXPECT_EQ(Process(s), kAllRan);
  for (const char* out : {"calibration/rig.json", "calibration/flash_positions.png", "slices/index.json", "ptm", "btf/index.json", "export/material.ptm",
                          "export/lp/material.lp", "export/btf/index.json", "report.html", "stages.json"})
    EXPECT_TRUE(fs::exists(s / out)) << out;
  auto report = ReadTextFile(s / "report.html");
  ASSERT_TRUE(report.ok());
  for (const char* shown : {"calibration/flash_positions.png", "report_files/light_coverage.png"})
    EXPECT_NE(report->find(shown), std::string::npos) << shown;
  // Skipped slices grouped by reason with counts, the full list folded away.
  auto slices = ReadJsonFile(s / "slices" / "index.json");
  ASSERT_TRUE(slices.ok());
  if (!slices->value("skipped", Json::array()).empty()) {
    EXPECT_NE(report->find("<th>reason</th><th>count</th><th>boards</th>"), std::string::npos);
    EXPECT_NE(report->find("<details><summary>Every one of the"), std::string::npos);
  }

  // Capture guidance on the processed session (issue 12).
  std::string guidance;
  ASSERT_EQ(testing::RunMesocap("coverage " + s.string(), &guidance), 0) << guidance;
  EXPECT_NE(guidance.find("next 1: move the flash"), std::string::npos) << guidance;
  auto coverage = ReadJsonFile(s / "coverage" / "coverage.json");
  ASSERT_TRUE(coverage.ok()) << coverage.status().message();
  EXPECT_EQ((*coverage)["lights_from"].get<std::string>(), "slices/index.json");
  const double score = (*coverage)["score"].get<double>();
  EXPECT_GT(score, 0.0);
  EXPECT_LT(score, 1.0);
  EXPECT_FALSE((*coverage)["next"].empty());
  for (const Json& next : (*coverage)["next"]) EXPECT_GT(next["targets_gained"].get<int>(), 0);
  EXPECT_TRUE(fs::exists(s / "coverage" / "coverage.png"));

  const Statuses all_skipped = {{"calibrate", "skipped"}, {"resample", "skipped"}, {"fit-ptm", "skipped"},
                                {"reconstruct", "skipped"}, {"export", "skipped"}};
  EXPECT_EQ(Process(s), all_skipped);

  // An option of one stage: that stage and those that read its outputs.
  EXPECT_EQ(Process(s, " --btf-size 64"), (Statuses{{"calibrate", "skipped"}, {"resample", "skipped"}, {"fit-ptm", "skipped"},
                                                   {"reconstruct", "ran"}, {"export", "ran"}}));
  auto btf = ReadSliceIndex(s / "btf" / "index.json");
  ASSERT_TRUE(btf.ok());
  auto slice = ReadImage(btf->slices.front().file);
  ASSERT_TRUE(slice.ok());
  EXPECT_EQ(slice->width(), 64);

  // A deleted output: its stage runs again.
  fs::path ptm_file;
  for (const auto& e : fs::directory_iterator(s / "ptm"))
    if (e.path().extension() == ".ptm") ptm_file = e.path();
  fs::remove(ptm_file);
  const Statuses after_delete = Process(s, " --btf-size 64");
  EXPECT_EQ(after_delete.at("fit-ptm"), "ran");
  EXPECT_EQ(after_delete.at("reconstruct"), "skipped");
  EXPECT_EQ(after_delete.at("calibrate"), "skipped");
  EXPECT_TRUE(fs::exists(ptm_file));

  // A build whose reconstruct stage changed (its version injected, as core/stage_versions.h
  // allows for tests): that stage and the one that reads it rerun, the others not.
  ::setenv("MESOCAP_STAGE_VERSIONS", "reconstruct=99", 1);
  const Statuses upgraded = Process(s, " --btf-size 64");
  ::unsetenv("MESOCAP_STAGE_VERSIONS");
  EXPECT_EQ(upgraded, (Statuses{{"calibrate", "skipped"}, {"resample", "skipped"}, {"fit-ptm", "skipped"},
                                {"reconstruct", "ran"}, {"export", "ran"}}));
  auto stages = StageCache::Open(s);
  ASSERT_TRUE(stages.ok());
  EXPECT_EQ(stages->Find("reconstruct")->version, 99);
  EXPECT_EQ(stages->Find("calibrate")->version, 1);

  // --force reruns a stage; the stages after it rerun because its outputs were rewritten.
  const Statuses forced = Process(s, " --btf-size 64 --force calibrate");
  EXPECT_EQ(forced.at("calibrate"), "ran");
  EXPECT_EQ(forced.at("resample"), "ran");
}

// Issue 12's account on a calibrated session: the reconstruction from the session's own slices,
// scored on held-out Bonn pairs against the material's true BTF.
TEST_F(ProcessTest, EvaluateScoresTheSessionsCalibratedSlicesAgainstItsTrueBtf) {
  const fs::path s = FreshSession();
  std::string out;
  ASSERT_EQ(testing::RunMesocap("calibrate " + s.string() + " --camera " + (s / "truth.json").string() +
                                    " --slice-size 32 --no-progress",
                                &out),
            0)
      << out;
  // simulate writes 4:2:0 JPEGs, as cameras do: the resample stage says what that costs.
  EXPECT_NE(out.find("JPEGs with colour at half resolution"), std::string::npos) << out;
  auto index = ReadSliceIndex(s / "slices" / "index.json");
  ASSERT_TRUE(index.ok());
  EXPECT_TRUE(index->chroma_subsampled_shots);
  ASSERT_EQ(testing::RunMesocap("evaluate --session " + s.string() + " --out " + (s / "evaluation").string() +
                                    " --size 16 --pairs 30 --no-progress",
                                &out),
            0)
      << out;
  EXPECT_NE(out.find("30 of "), std::string::npos) << out;
  auto eval = ReadJsonFile(s / "evaluation" / "evaluation.json");
  ASSERT_TRUE(eval.ok()) << eval.status().message();
  EXPECT_EQ((*eval)["held_out_pairs"].get<int>(), 30);
  EXPECT_GT((*eval)["held_out_pairs_total"].get<int>(), 30);
  EXPECT_EQ((*eval)["material"].get<std::string>(), "weave");  // simulate's default, from truth.json
  EXPECT_TRUE((*eval)["chroma_from_top"].get<bool>());  // chosen because the shots are 4:2:0 JPEGs
  const double lobe = (*eval)["white_lobe"]["strength"].get<double>();
  EXPECT_TRUE(lobe >= 0 && lobe <= WhiteLobe::kMaxStrength) << lobe;
  // The mean brightness model's check ran on the session's slices and its verdict follows its
  // figures. The virtual weave looks different from each view, so the model, fitted to all views,
  // must predict a left-out view's brightness well ahead of the top view's (here 1.6% against 5.0%).
  const Json& mean_model = (*eval)["mean_model"];
  EXPECT_GT(mean_model["slices"].get<int>(), 0);
  std::printf("mean model check: %d slices, median log error %.4f, top view's %.4f, used %d\n", mean_model["slices"].get<int>(),
              mean_model["model_median_log_error"].get<double>(), mean_model["top_view_median_log_error"].get<double>(),
              int(mean_model["used"].get<bool>()));
  EXPECT_EQ(mean_model["used"].get<bool>(),
            mean_model["model_median_log_error"].get<double>() < mean_model["top_view_median_log_error"].get<double>());
  EXPECT_TRUE(mean_model["used"].get<bool>());
  EXPECT_LT(mean_model["model_median_log_error"].get<double>(), 0.6 * mean_model["top_view_median_log_error"].get<double>());
  const int used = (*eval)["input_slices"].get<int>();
  EXPECT_GT(used, 0);
  EXPECT_LE(used, int(index->slices.size()));
  int by_coverage = 0;
  for (const char* c : {"inside", "near", "far"}) by_coverage += (*eval)["by_light_coverage"][c]["pairs"].get<int>();
  EXPECT_EQ(by_coverage, 30);
  // Held out: no pair is seen from a board's view (the mean of its slices' views).
  std::map<int, Eigen::Vector3d> board_views;
  for (const auto& slice : index->slices) {
    auto [it, added] = board_views.try_emplace(slice.board, Eigen::Vector3d::Zero());
    it->second += slice.view;
  }
  for (const Json& pair : (*eval)["pairs"]) {
    const Eigen::Vector3d view = DirectionFromAnglesDeg(pair["theta_o_deg"].get<double>(), pair["phi_o_deg"].get<double>());
    for (const auto& [board, sum] : board_views) EXPECT_GT(AngleBetweenDeg(view, sum.normalized()), 0.5) << board;
    for (const char* method : {"statistical", "top_view", "brdf_modulated"})
      EXPECT_TRUE(std::isfinite(pair[method]["w_pixels"].get<double>())) << method;
  }
  EXPECT_TRUE(fs::exists(s / "evaluation" / "sheet.png"));

  // --chroma-from-views overrides the shots' choice.
  ASSERT_EQ(testing::RunMesocap("evaluate --session " + s.string() + " --out " + (s / "evaluation_views").string() +
                                    " --size 16 --pairs 30 --no-progress --chroma-from-views",
                                &out),
            0)
      << out;
  auto views = ReadJsonFile(s / "evaluation_views" / "evaluation.json");
  ASSERT_TRUE(views.ok()) << views.status().message();
  EXPECT_FALSE((*views)["chroma_from_top"].get<bool>());
  EXPECT_NE(testing::RunMesocap("evaluate --session " + s.string() + " --out " + (s / "evaluation_both").string() +
                                    " --chroma-from-views --chroma-from-top",
                                &out),
            0);
  EXPECT_NE(out.find("excludes"), std::string::npos) << out;
}

TEST_F(ProcessTest, AKilledRunResumesAtItsStageAndShowsNothingHalfWritten) {
  const fs::path s = FreshSession();
  ASSERT_EQ(Process(s), kAllRan);
  auto before = ReadSliceIndex(s / "btf" / "index.json");
  ASSERT_TRUE(before.ok());

  // The full Bonn grid takes seconds to reconstruct: kill -9 once its staging folder appears.
  const std::string command = testing::MesocapBinary() + " process " + s.string() + Options(s, " --btf-grid bonn");
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", ("exec " + command + " >/dev/null 2>&1").c_str(), nullptr);
    ::_exit(127);
  }
  bool seen = false;
  for (int k = 0; k < 6000 && !seen; ++k) {
    for (const auto& e : fs::directory_iterator(s))
      if (e.path().filename().string().rfind(".btf.partial-", 0) == 0) seen = true;
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  // A second writer meanwhile is refused, with the holder named, and changes nothing.
  std::string refused;
  EXPECT_EQ(testing::RunMesocap("process " + s.string() + Options(s, " --btf-grid bonn"), &refused), 1) << refused;
  EXPECT_NE(refused.find("is being written by mesocap process (pid " + std::to_string(pid) + " on host"), std::string::npos)
      << refused;
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(seen) << "the reconstruct stage never started";
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run finished before it could be killed";

  // What is in view is the previous, complete BTF.
  auto after_kill = ReadSliceIndex(s / "btf" / "index.json");
  ASSERT_TRUE(after_kill.ok());
  EXPECT_EQ(after_kill->slices.size(), before->slices.size());

  std::string out;
  ASSERT_EQ(testing::RunMesocap("process " + s.string() + Options(s, " --btf-grid bonn"), &out), 0) << out;
  for (const char* skipped : {"calibrate", "resample", "fit-ptm"})
    EXPECT_NE(out.find(std::string(skipped) + ": unchanged, skipped"), std::string::npos) << out;
  EXPECT_NE(out.find("reconstruct: running"), std::string::npos) << out;
  auto resumed = ReadSliceIndex(s / "btf" / "index.json");
  ASSERT_TRUE(resumed.ok());
  EXPECT_EQ(resumed->slices.size(), 81u * 81u);
  for (const auto& e : fs::directory_iterator(s))
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << "left behind: " << e.path();
  // stages.json, rewritten by one writer at a time, is whole and names every stage.
  auto stages = StageCache::Open(s);
  ASSERT_TRUE(stages.ok()) << stages.status().message();
  for (const char* stage : {"calibrate", "resample", "fit-ptm", "reconstruct", "export"})
    EXPECT_NE(stages->Find(stage), nullptr) << stage;
}

TEST_F(ProcessTest, ExportsReadBackAsTheStagesWroteThem) {
  const fs::path s = FreshSession();
  ASSERT_EQ(Process(s), kAllRan);
  const fs::path out = testing::MakeTempDir() / "exported";
  std::string log;
  ASSERT_EQ(testing::RunMesocap("export " + s.string() + " --format ptm --format lp --format exr --multipart --format gltf --out " +
                                    out.string(),
                                &log),
            0)
      << log;

  // gltf: a material the Khronos validator accepts without a warning, beside its fit error map.
  EXPECT_EQ(testing::ValidateGltf(out / "gltf" / "material.gltf", &log), 0) << log;
  EXPECT_EQ(testing::ValidateGltf(s / "export" / "gltf" / "material.gltf", &log), 0) << log;
  for (const char* file : {"fit_error.png", "fit_error.exr", "fit.json", "base_color.png", "normal.png"})
    EXPECT_TRUE(fs::exists(out / "gltf" / file)) << file;

  // exr: index.json lists every slice file, and each holds exactly the reconstruction (half floats).
  auto index = ReadSliceIndex(out / "btf" / "index.json");
  ASSERT_TRUE(index.ok()) << index.status().message();
  std::set<fs::path> listed, on_disk;
  for (const auto& e : index->slices) listed.insert(e.file.lexically_normal());
  for (const auto& e : fs::recursive_directory_iterator(out / "btf" / "slices")) on_disk.insert(e.path().lexically_normal());
  EXPECT_EQ(listed, on_disk);
  EXPECT_EQ(listed.size(), 17u * 17u);
  SliceSetOptions options;
  options.size = 32;
  SliceSetReport loaded;
  auto btf = LoadStatisticalBtf(s / "slices" / "index.json", options, &loaded);
  ASSERT_TRUE(btf.ok()) << btf.status().message();
  for (size_t k : {size_t(0), size_t(100), index->slices.size() - 1}) {
    const SliceIndexEntry& e = index->slices[k];
    auto stored = ReadImage(e.file);
    ASSERT_TRUE(stored.ok());
    const Image truth = btf->Reconstruct(e.light, e.view);
    ASSERT_EQ(stored->size(), truth.size());
    size_t differ = 0;
    for (size_t i = 0; i < truth.size(); ++i)
      differ += stored->data()[i] != float(Eigen::half(truth.data()[i]));
    EXPECT_EQ(differ, 0u) << e.file;
  }
  // The multi-part EXR: one part per slice, in index order, named by the slice, with its
  // directions, and bit-identical to the slice file.
  for (size_t k : {size_t(0), size_t(57), index->slices.size() - 1}) {
    const SliceIndexEntry& e = index->slices[k];
    ImageInfo info;
    auto part = ReadImage(out / "btf.exr", {.part = int(k)}, &info);
    ASSERT_TRUE(part.ok()) << part.status().message();
    EXPECT_EQ(std::get<std::string>(info.attributes.at("name")), e.file.stem().string());
    EXPECT_NEAR(std::get<float>(info.attributes.at("mesocap:theta_i_deg")), e.theta_i_deg, 1e-4);
    EXPECT_NEAR(std::get<float>(info.attributes.at("mesocap:phi_o_deg")), e.phi_o_deg, 1e-4);
    auto slice = ReadImage(e.file);
    ASSERT_TRUE(slice.ok());
    ASSERT_EQ(part->size(), slice->size());
    EXPECT_TRUE(std::equal(part->data(), part->data() + part->size(), slice->data())) << k;
  }
  EXPECT_FALSE(ReadImageInfo(out / "btf.exr", int(index->slices.size())).ok());

  // ptm: the top board's PTM, relit identically from the exported file.
  auto exported = ReadPtmFile(out / "material.ptm");
  ASSERT_TRUE(exported.ok()) << exported.status().message();
  std::string top_ptm;
  for (const auto& e : fs::directory_iterator(s / "ptm"))
    if (e.path().extension() == ".ptm") {
      auto candidate = ReadPtmFile(e.path());
      ASSERT_TRUE(candidate.ok());
      const Eigen::Vector3d light = DirectionFromAnglesDeg(40, 70);
      const Image a = RelightPtm(*candidate, light), b = RelightPtm(*exported, light);
      if (a.size() == b.size() && std::equal(a.data(), a.data() + a.size(), b.data())) top_ptm = e.path().filename();
    }
  EXPECT_FALSE(top_ptm.empty()) << "material.ptm relights as none of the boards' PTMs";

  // lp: the top board's slices with their light directions; fit-ptm reads it as an RTI capture.
  auto lp = ReadLpFile(out / "lp" / "material.lp");
  ASSERT_TRUE(lp.ok()) << lp.status().message();
  auto slices = ReadSliceIndex(s / "slices" / "index.json");
  ASSERT_TRUE(slices.ok());
  const int top_board = std::stoi(top_ptm.substr(6, 2));
  std::vector<Eigen::Vector3d> top_lights;
  for (const auto& e : slices->slices)
    if (e.board == top_board) top_lights.push_back(e.light);
  ASSERT_EQ(lp->size(), top_lights.size());
  for (size_t k = 0; k < top_lights.size(); ++k) EXPECT_LT(((*lp)[k].light_dir - top_lights[k]).norm(), 1e-5);
  EXPECT_EQ(testing::RunMesocap("fit-ptm --lp " + (out / "lp" / "material.lp").string() + " --out " +
                                    (out / "refit.ptm").string() + " --no-progress",
                                &log),
            0)
      << log;
}

TEST_F(ProcessTest, SynthesisWhenAskedEnlargesTheBtfAndItsGltfMaterial) {
  const fs::path s = FreshSession();
  ASSERT_EQ(Process(s), kAllRan);
  std::map<std::string, std::string> with_synth = Process(s, " --synth quilt --synth-size 80x48");
  EXPECT_EQ(with_synth, (Statuses{{"calibrate", "skipped"}, {"resample", "skipped"}, {"fit-ptm", "skipped"},
                                  {"reconstruct", "skipped"}, {"synth", "ran"}, {"export", "ran"}}));
  std::string out;
  ASSERT_EQ(testing::RunMesocap("process " + s.string() + Options(s, " --synth quilt --synth-size 80x48"), &out), 0) << out;
  EXPECT_NE(out.find("synth: unchanged, skipped"), std::string::npos) << out;
  auto index = ReadSliceIndex(s / "synth" / "index.json");
  ASSERT_TRUE(index.ok()) << index.status().message();
  EXPECT_EQ(index->slices.size(), 17u * 17u);
  auto slice = ReadImage(index->slices.front().file);
  ASSERT_TRUE(slice.ok());
  EXPECT_EQ(slice->width(), 80);
  EXPECT_EQ(slice->height(), 48);
  EXPECT_EQ(testing::ValidateGltf(s / "export" / "gltf_synth" / "material.gltf", &out), 0) << out;
  auto base = ReadImage(s / "export" / "gltf_synth" / "base_color.png");
  ASSERT_TRUE(base.ok());
  EXPECT_EQ(base->width(), 80);

  // A new reconstruction without synthesis: synth/ was made from the old BTF (the stage cache
  // says so, whatever the files' times), so the export leaves the synthesized material out.
  EXPECT_EQ(Process(s, " --btf-size 64").at("reconstruct"), "ran");
  EXPECT_FALSE(fs::exists(s / "export" / "gltf_synth"));
  EXPECT_TRUE(fs::exists(s / "export" / "gltf" / "material.gltf"));
  // Even with its map touched after the new BTF (a copy, a restore): times are not the rule.
  fs::last_write_time(s / "synth" / "map.exr", fs::file_time_type::clock::now() + std::chrono::hours(1));
  ASSERT_EQ(testing::RunMesocap("export " + s.string() + " --format gltf", &out), 0) << out;
  EXPECT_FALSE(fs::exists(s / "export" / "gltf_synth")) << out;
}

// --decorate: each mesh dressed after export into decorate/<name>/ (map, previews, a light sweep
// the report animates, a glTF asset that validates); cached like every stage: a rerun skips it,
// a changed mesh file reruns it; --decorate-method quilt adds decorate/<name>-quilt/.
TEST_F(ProcessTest, DecorateWhenAskedDressesEachMeshAfterExport) {
  const fs::path s = FreshSession(), meshes = testing::MakeTempDir();
  ASSERT_EQ(Process(s), kAllRan);
  ASSERT_TRUE(WriteObj(meshes / "ball.obj", IcoSphere(3)).ok());
  ASSERT_TRUE(WriteObj(meshes / "ring.obj", Torus(48, 16)).ok());
  const std::string decorate = " --decorate " + (meshes / "ball.obj").string() + " --decorate " + (meshes / "ring.obj").string();
  EXPECT_EQ(Process(s, decorate), (Statuses{{"calibrate", "skipped"}, {"resample", "skipped"}, {"fit-ptm", "skipped"},
                                            {"reconstruct", "skipped"}, {"export", "skipped"}, {"decorate", "ran"}}));
  for (const char* name : {"ball", "ring"}) {
    const fs::path d = s / "decorate" / name;
    for (const char* f : {"surface_map.ply", "report.json", "previews/light_0.png", "previews/sweep_11.png", "gltf/base_color.png"})
      EXPECT_TRUE(fs::exists(d / f)) << name << " " << f;
    std::string out;
    EXPECT_EQ(testing::ValidateGltf(d / "gltf" / "material.gltf", &out), 0) << out;
  }
  auto html = ReadTextFile(s / "report.html");
  ASSERT_TRUE(html.ok());
  EXPECT_NE(html->find("decorate/ring/previews/sweep_00.png"), std::string::npos);
  EXPECT_EQ(Process(s, decorate).at("decorate"), "skipped");
  ASSERT_TRUE(WriteObj(meshes / "ring.obj", Torus(40, 16)).ok());
  EXPECT_EQ(Process(s, decorate).at("decorate"), "ran");
  // Both methods: quilts beside the texton maps, in the report too; the methods are in the key.
  const std::string both = decorate + " --decorate-method texton --decorate-method quilt";
  EXPECT_EQ(Process(s, both).at("decorate"), "ran");
  for (const char* name : {"ball-quilt", "ring-quilt"}) {
    const fs::path d = s / "decorate" / name;
    for (const char* f : {"surface_map.ply", "atlas_map.exr", "previews/sweep_11.png", "gltf/base_color.png"})
      EXPECT_TRUE(fs::exists(d / f)) << name << " " << f;
  }
  EXPECT_TRUE(fs::exists(s / "decorate" / "ring" / "textons.exr"));
  html = ReadTextFile(s / "report.html");
  ASSERT_TRUE(html.ok());
  EXPECT_NE(html->find("decorate/ring-quilt/previews/sweep_00.png"), std::string::npos);
}

TEST_F(ProcessTest, TheReportRelightsInAHeadlessBrowserWithoutErrors) {
  const fs::path s = FreshSession();
  ASSERT_EQ(Process(s), kAllRan);
  std::string log;
  const std::string dom = testing::HeadlessDom("file://" + (s / "report.html").string() + "#selftest", &log);
  ASSERT_FALSE(dom.empty()) << log;
  // The page counts script errors and console.error calls into <body data-errors>.
  EXPECT_NE(dom.find("data-errors=\"0\""), std::string::npos) << dom.substr(0, 2000) << log;
  for (const char* canvas : {"mesocap-viewer-ptm", "mesocap-viewer-btf"}) EXPECT_NE(dom.find(canvas), std::string::npos);
  // The self-test moved the light across each canvas: most pixels must change.
  const size_t at = dom.find("data-selftest=\"");
  ASSERT_NE(at, std::string::npos) << "the self-test did not finish";
  std::string result = dom.substr(at + 15, dom.find('"', at + 15) - at - 15);
  for (size_t q; (q = result.find("&quot;")) != std::string::npos;) result.replace(q, 6, "\"");
  const Json selftest = Json::parse(result);
  ASSERT_EQ(selftest.value("canvases", 0), 2) << result;
  for (const Json& changed : selftest["changed"]) EXPECT_GT(changed.get<double>(), 0.5) << result;
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;
}

// A lab's offline case: the photos as a plain folder, imported (`mesocap import`, no journal of
// the virtual camera, no layout) and processed with the layout given: every stage runs and the
// calibration and slices come out as from the virtual session itself.
TEST_F(ProcessTest, AnImportedPhotoFolderProcessesLikeTheSessionItCameFrom) {
  const fs::path virtual_session = FreshSession();
  ASSERT_EQ(Process(virtual_session), kAllRan);
  const fs::path photos = testing::MakeTempDir() / "photos";
  fs::create_directories(photos);
  for (const auto& e : fs::directory_iterator(virtual_session / "shots")) fs::copy_file(e.path(), photos / e.path().filename());
  const fs::path imported = testing::MakeTempDir() / "imported";
  std::string out;
  ASSERT_EQ(testing::RunMesocap("import " + photos.string() + " --out " + imported.string() + " --no-progress", &out), 0) << out;
  EXPECT_FALSE(fs::exists(imported / "rig_layout.json"));
  const std::string layout = " --layout " + (virtual_session / "rig_layout.json").string() + " --camera " +
                             (virtual_session / "truth.json").string();
  ASSERT_EQ(Process(imported, layout), kAllRan);
  auto rig = ReadJsonFile(imported / "calibration" / "rig.json"), original = ReadJsonFile(virtual_session / "calibration" / "rig.json");
  ASSERT_TRUE(rig.ok() && original.ok());
  ASSERT_EQ(rig->at("shots").size(), original->at("shots").size());
  for (size_t k = 0; k < rig->at("shots").size(); ++k) {
    const Json& a = rig->at("shots")[k];
    const Json& b = original->at("shots")[k];
    ASSERT_EQ(a.at("ok"), b.at("ok")) << k;
    if (a.at("ok").get<bool>()) {
      // Within a micrometre: calibration sums the shots in thread order, so the last bits vary.
      EXPECT_LT((JsonVector3d(a.at("light_m"), "light_m", 1e3) - JsonVector3d(b.at("light_m"), "light_m", 1e3)).norm(), 1e-6)
          << k;
    }
  }
  auto slices = ReadSliceIndex(imported / "slices" / "index.json"), original_slices = ReadSliceIndex(virtual_session / "slices" / "index.json");
  ASSERT_TRUE(slices.ok() && original_slices.ok());
  EXPECT_EQ(slices->slices.size(), original_slices->slices.size());
  EXPECT_TRUE(fs::exists(imported / "export" / "gltf" / "material.gltf"));
  EXPECT_EQ(Process(imported, layout), (Statuses{{"calibrate", "skipped"}, {"resample", "skipped"}, {"fit-ptm", "skipped"},
                                                 {"reconstruct", "skipped"}, {"export", "skipped"}}));
}

TEST_F(ProcessTest, MissingStagesAndBadOptionsAreNamedWithTheCommandThatFixesThem) {
  const fs::path s = FreshSession();
  std::string out;
  EXPECT_EQ(testing::RunMesocap("export " + s.string() + " --format ptm", &out), 1);
  EXPECT_NE(out.find("mesocap process " + s.string()), std::string::npos) << out;
  EXPECT_EQ(testing::RunMesocap("export " + s.string() + " --format gltf", &out), 1) << out;
  EXPECT_NE(out.find("btf/index.json not found"), std::string::npos) << out;
  EXPECT_NE(out.find("mesocap process " + s.string()), std::string::npos) << out;
  EXPECT_EQ(testing::RunMesocap("export " + s.string() + " --format usd", &out), 2) << out;
  EXPECT_EQ(testing::RunMesocap("process " + s.string() + " --force everything --no-progress", &out), 2) << out;
  EXPECT_EQ(testing::RunMesocap("process " + s.string() + " --btf-grid fine --no-progress", &out), 2) << out;
  EXPECT_EQ(testing::RunMesocap("process " + (s / "nope").string() + " --no-progress", &out), 1) << out;
  EXPECT_NE(out.find("nope"), std::string::npos) << out;
  std::ofstream(s / "stages.json") << "{ torn";
  EXPECT_EQ(testing::RunMesocap("process " + s.string() + Options(s), &out), 1) << out;
  EXPECT_NE(out.find("stages.json"), std::string::npos) << out;
}

}  // namespace
}  // namespace mesocap
