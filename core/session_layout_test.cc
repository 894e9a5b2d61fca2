// The session layout: its names round-trip, and no source file but core/session_layout.cc
// spells them as paths (tests, benchmarks, fuzzers and docs aside).
#include "core/session_layout.h"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace mesocap {
namespace {
namespace fs = std::filesystem;

TEST(SessionLayout, ShotNamesRoundTrip) {
  EXPECT_EQ(SessionLayout::ShotEntry("shot", 7, ".jpg"), "shots/shot_0007.jpg");
  EXPECT_EQ(SessionLayout::ShotEntry("calib", 12, ".png"), "calib/calib_0012.png");
  EXPECT_EQ(SessionLayout::ShotIndexOf("shot", "shot_0007.jpg"), 7);
  EXPECT_EQ(SessionLayout::ShotIndexOf("shot", "shot_123456.cr2"), 123456);
  EXPECT_EQ(SessionLayout::ShotIndexOf("calib", "shot_0007.jpg"), 0) << "another kind";
  EXPECT_EQ(SessionLayout::ShotIndexOf("shot", "shot_0007"), 0) << "no extension: not a shot (a temp name)";
  EXPECT_EQ(SessionLayout::ShotIndexOf("shot", "shot_12x4.jpg"), 0);
  EXPECT_EQ(SessionLayout::ShotIndexOf("shot", "shot_1234567.jpg"), 0) << "more digits than any index";
  const SessionLayout layout("/data/s1");
  EXPECT_EQ(layout.shots_of_kind("calib"), layout.calib());
  EXPECT_EQ(layout.shots_of_kind("shot"), layout.shots());
  EXPECT_EQ(layout.Relative(layout.root() / SessionLayout::ShotEntry("shot", 3, ".jpg")), "shots/shot_0003.jpg");
}

TEST(SessionLayout, EveryPathIsInsideTheSessionAndNamedOnce) {
  const SessionLayout layout("/data/s1");
  const Json j = layout.ToJson();
  EXPECT_EQ(j["root"], "/data/s1");
  std::set<std::string> paths;
  std::function<void(const Json&, const std::string&)> visit = [&](const Json& node, const std::string& at) {
    for (const auto& [key, value] : node.items()) {
      if (value.is_object()) {
        visit(value, at + key + ".");
      } else if (value.is_string() && !at.empty()) {
        const std::string path = value.get<std::string>();
        EXPECT_FALSE(path.empty() || path[0] == '/' || path.find("..") != std::string::npos) << at << key << ": " << path;
        // A BTF folder inside another folder shares that folder's root ("folder"), nothing else repeats.
        if (key != "folder") {
          EXPECT_TRUE(paths.insert(path).second) << at << key << " repeats " << path;
        }
      }
    }
  };
  visit(j, "");
  EXPECT_GT(paths.size(), 60u);
}

// The names the layout spells, as the path components of every path it prints; a component with
// a placeholder (board_BB.lp) stands for its fixed part before the placeholder (board_).
std::set<std::string> LayoutComponents() {
  std::set<std::string> components;
  std::function<void(const Json&)> visit = [&](const Json& node) {
    for (const auto& [key, value] : node.items()) {
      if (value.is_object()) visit(value);
      if (!value.is_string() || key == "root" || key == "note" || key == "format") continue;
      for (const auto& part : fs::path(value.get<std::string>())) components.insert(part.string());
    }
  };
  visit(SessionLayout("s").ToJson());
  components.insert(ReportHtmlName());
  components.insert(ReportMarkdownName());
  return components;
}

// `line` without its // comment (a // inside a string literal is kept).
std::string WithoutComment(const std::string& line) {
  bool in_string = false;
  for (size_t i = 0; i + 1 < line.size(); ++i) {
    if (line[i] == '"' && (i == 0 || line[i - 1] != '\\')) in_string = !in_string;
    if (!in_string && line[i] == '/' && line[i + 1] == '/') return line.substr(0, i);
  }
  return line;
}

std::string RegexEscape(const std::string& s) {
  static const std::regex special(R"([.^$|()\[\]{}*+?\\])");
  return std::regex_replace(s, special, R"(\$&)");
}

// How `name` shows when code spells it as a path: a file name (it has an extension) in any string
// literal without spaces, as the whole literal or one of its '/'-separated parts; a folder name
// joined with `/` (`dir / "slices"`) or inside a literal of several parts ("slices/index.json").
// A folder name alone in quotes is also a JSON key or a stage name ("slices", "export"), so that
// form is not counted.
std::regex SpellingOf(const std::string& name) {
  // A patterned name (board_BB.lp, shot_NNNN.jpg, preview_lightK.png) by its fixed part before the
  // placeholder, as a printf format or a literal joined to a number: "board_%02d.lp", "board_" + ...
  for (const char* placeholder : {"BB", "NNNN", "KKKK", "K."})
    if (const size_t at = name.find(placeholder); at != std::string::npos)
      return std::regex("\"" + RegexEscape(name.substr(0, at)) + "(%|\")");
  const std::string n = RegexEscape(name);
  const std::string part = R"([^"\s]*)";
  if (name.find('.') != std::string::npos && name[0] != '.')
    return std::regex("\"(" + part + "/)?" + n + "(/" + part + ")?\"");
  if (name[0] == '.') return std::regex("\"" + n + "\"");  // .mesocap.lock
  return std::regex("/\\s*\"" + n + "[\"/]|\"" + part + "/" + n + "[\"/]|\"" + n + "/" + part + "\"");
}

TEST(SessionLayout, NoOtherSourceSpellsTheSessionsNames) {
  const fs::path root = MESOCAP_SOURCE_DIR;
  std::vector<std::pair<std::string, std::regex>> spellings;
  for (const std::string& name : LayoutComponents()) spellings.emplace_back(name, SpellingOf(name));
  ASSERT_GT(spellings.size(), 40u);
  int files = 0;
  std::vector<std::string> found;
  for (const char* dir : {"app", "core", "capture", "calib", "reconstruct", "synth", "export"}) {
    for (const auto& entry : fs::recursive_directory_iterator(root / dir)) {
      const fs::path& path = entry.path();
      const std::string file = path.filename().string();
      if (path.extension() != ".cc" && path.extension() != ".h") continue;
      if (file.find("_test") != std::string::npos || file.find("test_support") != std::string::npos) continue;
      if (path == root / "core" / "session_layout.cc") continue;
      ++files;
      std::ifstream in(path);
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        const std::string code = WithoutComment(line);
        if (code.find("#include") != std::string::npos) continue;
        for (const auto& [name, spelling] : spellings)
          if (std::regex_search(code, spelling))
            found.push_back(fs::relative(path, root).string() + ":" + std::to_string(number) + ": " + name + ": " + line);
      }
    }
  }
  EXPECT_GT(files, 200);
  std::ostringstream list;
  for (const std::string& f : found) list << f << "\n";
  EXPECT_TRUE(found.empty()) << "session names spelled outside core/session_layout.cc (use SessionLayout):\n" << list.str();
}

// The check itself finds each form it is meant to find.
TEST(SessionLayout, TheSpellingCheckFindsEachForm) {
  EXPECT_TRUE(std::regex_search(R"(session / "calibration" / x)", SpellingOf("calibration")));
  EXPECT_TRUE(std::regex_search(R"(f("slices/index.json"))", SpellingOf("slices")));
  EXPECT_TRUE(std::regex_search(R"(f("slices/index.json"))", SpellingOf("index.json")));
  EXPECT_TRUE(std::regex_search(R"(dir / "rig.json")", SpellingOf("rig.json")));
  EXPECT_TRUE(std::regex_search(R"(Format("board_%02d.ptm", b))", SpellingOf("board_BB.ptm")));
  EXPECT_TRUE(std::regex_search(R"("preview_light" + k)", SpellingOf("preview_lightK.png")));
  EXPECT_TRUE(std::regex_search(R"(p / ".mesocap.lock")", SpellingOf(".mesocap.lock")));
  EXPECT_FALSE(std::regex_search(R"(j["slices"] = list;)", SpellingOf("slices"))) << "a JSON key";
  EXPECT_FALSE(std::regex_search(R"(stage("export", after))", SpellingOf("export"))) << "a stage name";
  EXPECT_FALSE(std::regex_search(R"(Error("see SESSION/calibration/ for more"))", SpellingOf("rig.json")));
}

}  // namespace
}  // namespace mesocap
