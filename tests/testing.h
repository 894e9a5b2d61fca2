// Shared test helpers: per-test temp folders, seeds derived from the test name (one seed
// reproduces a failure), and running the real CLI.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace mesocap::testing {

// A fresh empty folder under the system temp dir, named after the current test. Removed when
// the test (or, made outside a test, the whole program) passes, kept when it fails.
std::filesystem::path MakeTempDir();
// A stable seed from the current test's full name.
uint32_t SeedFromTestName();
// Path of the mesocap executable (from $MESOCAP_BIN, set by ctest).
std::string MesocapBinary();
// Runs a shell command (sh), its stdout (and whatever it redirects there) into *output; returns
// the exit code.
int RunCommand(const std::string& command, std::string* output = nullptr);
// Runs `mesocap ARGS`, capturing stdout+stderr into *output; returns the exit code.
int RunMesocap(const std::string& args, std::string* output = nullptr);
// Runs the Khronos glTF validator on `gltf` (scripts/validate-gltf.mjs, node + the npm package
// install-deps installs); returns its exit code: 0 no errors and no warnings, 1 some, 2 missing.
int ValidateGltf(const std::filesystem::path& gltf, std::string* output = nullptr);
// The document `url` leaves after its scripts ran, from headless Chromium (software WebGL);
// empty when Chromium is missing or failed (then *log says why).
std::string HeadlessDom(const std::string& url, std::string* log = nullptr);

}  // namespace mesocap::testing
