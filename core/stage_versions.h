// Each `process` stage's algorithm version, part of the stage's cache key (SESSION/stages.json):
// a build whose stage writes something different for the same inputs and options must bump that
// stage's version here, so a session processed by an older build reruns the stage (and, through
// the key, every stage that reads its outputs) instead of keeping stale results.
// `app/stage_versions_test.cc` records a small output's digest to catch a forgotten bump.
#pragma once

#include <string>

#include "core/json.h"

namespace mesocap {

// The stage's version; 0 for a name that is not a stage. MESOCAP_STAGE_VERSIONS
// ("reconstruct=7,synth=2") overrides entries: a changed build, for tests, without rebuilding.
int StageVersion(const std::string& stage);
// {"calibrate": 1, ...}: every stage's version, as provenance records them.
Json StageVersions();

}  // namespace mesocap
