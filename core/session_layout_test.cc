// The session layout: its names round-trip, and no source file but core/session_layout.cc
// spells them as paths (tests, benchmarks, fuzzers and docs aside).
#include "core/session_layout.h"

#include <gtest/gtest.h>

#include <fstream>
#include <optional>
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

// Whether `line` (code, comment removed) spells `name` in a string literal: a file name (one with
// an extension) anywhere in a literal, as a word; a folder name next to a '/' in a literal
// ("slices/index.json", "SESSION/calibration/") or joined to a path (`dir / "slices"`); a
// patterned name by its fixed part before a number ("board_%02d.lp", "board_" + ...). A folder
// name alone in quotes is also a JSON key or a stage name ("slices", "export"), so that form is
// not counted.
class Spelling {
 public:
  explicit Spelling(const std::string& name) {
    std::string fixed;
    for (const char* placeholder : {"BB", "NNNN", "KKKK", "K."})
      if (const size_t at = name.find(placeholder); at != std::string::npos && fixed.empty()) fixed = name.substr(0, at);
    if (!fixed.empty()) {
      in_literal_ = std::regex("(^|[^A-Za-z0-9_])" + RegexEscape(fixed) + "(%|$)");
    } else if (name.find('.') != std::string::npos) {
      in_literal_ = std::regex("(^|[^A-Za-z0-9_])" + RegexEscape(name) + "($|[^A-Za-z0-9_])");
    } else {
      const std::string n = RegexEscape(name);
      in_literal_ = std::regex("(^|[^A-Za-z0-9_.-])" + n + "/|/" + n + "($|[^A-Za-z0-9_.-])");
      joined_ = std::regex("/\\s*\"" + n + "\"");
    }
  }
  // `literals`: the contents of the line's string literals.
  bool In(const std::string& line, const std::vector<std::string>& literals) const {
    if (joined_ && std::regex_search(line, *joined_)) return true;
    for (const std::string& l : literals)
      if (std::regex_search(l, in_literal_)) return true;
    return false;
  }

 private:
  std::regex in_literal_;
  std::optional<std::regex> joined_;
};

std::vector<std::string> LiteralsOf(const std::string& line) {
  static const std::regex literal(R"re("((?:[^"\\]|\\.)*)")re");
  std::vector<std::string> literals;
  for (auto it = std::sregex_iterator(line.begin(), line.end(), literal); it != std::sregex_iterator(); ++it)
    literals.push_back((*it)[1].str());
  return literals;
}

bool Spells(const std::string& line, const std::string& name) { return Spelling(name).In(line, LiteralsOf(line)); }

TEST(SessionLayout, NoOtherSourceSpellsTheSessionsNames) {
  const fs::path root = MESOCAP_SOURCE_DIR;
  std::vector<std::pair<std::string, Spelling>> spellings;
  for (const std::string& name : LayoutComponents()) spellings.emplace_back(name, Spelling(name));
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
        if (code.find('"') == std::string::npos) continue;
        const std::vector<std::string> literals = LiteralsOf(code);
        for (const auto& [name, spelling] : spellings)
          if (spelling.In(code, literals))
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
  EXPECT_TRUE(Spells(R"x(session / "calibration" / x)x", "calibration"));
  EXPECT_TRUE(Spells(R"x(f("slices/index.json"))x", "slices"));
  EXPECT_TRUE(Spells(R"x(f("slices/index.json"))x", "index.json"));
  EXPECT_TRUE(Spells(R"x(dir / "rig.json")x", "rig.json"));
  EXPECT_TRUE(Spells(R"x(help("Rig layout (default SESSION/rig_layout.json)"))x", "rig_layout.json"));
  EXPECT_TRUE(Spells(R"x(help("writes SESSION/calibration/ whole"))x", "calibration"));
  EXPECT_TRUE(Spells(R"x(help("into calib/ instead"))x", "calib"));
  EXPECT_TRUE(Spells(R"x(Format("board_%02d.ptm", b))x", "board_BB.ptm"));
  EXPECT_TRUE(Spells(R"x("preview_light" + k)x", "preview_lightK.png"));
  EXPECT_TRUE(Spells(R"x(p / ".mesocap.lock")x", ".mesocap.lock"));
  EXPECT_FALSE(Spells(R"x(j["slices"] = list;)x", "slices")) << "a JSON key";
  EXPECT_FALSE(Spells(R"x(stage("export", after))x", "export")) << "a stage name";
  EXPECT_FALSE(Spells(R"x(Error("see the calibration shots"))x", "calibration")) << "a word";
  EXPECT_FALSE(Spells(R"x(f("import_report.json"))x", "report.json")) << "another name's part";
  EXPECT_FALSE(Spells(R"x(f("calibration/"))x", "calib"));
}

}  // namespace
}  // namespace mesocap
