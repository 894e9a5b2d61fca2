// The libraries' layers: a folder's sources (tests aside) include only their own folder's headers
// and those of the layers below, so a reader of a file format, say, never pulls in the export.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

namespace mesocap {
namespace {
namespace fs = std::filesystem;

TEST(Layering, EachLibraryIncludesOnlyItsOwnAndLowerLayers) {
  const std::map<std::string, std::set<std::string>> may_include = {
      {"core", {"core"}},
      {"capture", {"core", "capture"}},
      {"calib", {"core", "capture", "calib"}},
      {"reconstruct", {"core", "reconstruct"}},
      {"formats", {"core", "reconstruct", "formats"}},  // .ptm and .lp: below every stage that reads them
      {"synth", {"core", "reconstruct", "formats", "synth"}},
      {"mesh", {"core", "reconstruct", "formats", "synth", "mesh"}},
      {"export", {"core", "reconstruct", "formats", "export"}},
  };
  const fs::path root = MESOCAP_SOURCE_DIR;
  const std::regex include(R"(^\s*#include\s+"([a-z_]+)/)");
  std::string found;
  int files = 0;
  for (const auto& [dir, allowed] : may_include)
    for (const auto& entry : fs::recursive_directory_iterator(root / dir)) {
      const std::string name = entry.path().filename().string();
      if ((entry.path().extension() != ".cc" && entry.path().extension() != ".h") ||
          name.find("_test") != std::string::npos || name.find("test_support") != std::string::npos)
        continue;
      ++files;
      std::ifstream in(entry.path());
      std::string line;
      std::smatch m;
      for (int number = 1; std::getline(in, line); ++number)
        if (std::regex_search(line, m, include) && !allowed.count(m[1].str()))
          found += fs::relative(entry.path(), root).string() + ":" + std::to_string(number) + ": " + line + "\n";
    }
  EXPECT_GT(files, 150);
  EXPECT_TRUE(found.empty()) << "includes from a higher layer:\n" << found;
}

}  // namespace
}  // namespace mesocap
