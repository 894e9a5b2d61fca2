// mesocap process SESSION: every stage from the shots to the exports (app/process.h), a summary
// table and SESSION/report.html.
#include "app/process_args.h"

#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "app/process.h"
#include "app/synth_output.h"
#include "core/json.h"
#include "core/session_layout.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

Json OutcomesToJson(const fs::path& session, const std::vector<StageOutcome>& outcomes) {
  Json stages = Json::array();
  for (const StageOutcome& o : outcomes)
    stages.push_back({{"stage", o.name}, {"status", o.status}, {"seconds", o.seconds}, {"brief", o.summary.brief},
                      {"warnings", o.summary.warnings}});
  return {{"format", "mesocap-process-outcome"}, {"session", fs::absolute(session).lexically_normal().string()},
          {"stages", stages}};
}

}  // namespace

int RunProcess(ProcessArgs& a) {
  const std::string verb = "process";
  if (!StringToPtmFormat(a.ptm_format, &a.options.ptm.format))
    return Fail(verb, "--ptm-format must be lrgb or rgb, not '" + a.ptm_format + "'", kExitUsage);
  a.options.resample.brdf_smoothing = !a.no_brdf_smoothing;
  a.options.resample.restore_chroma_detail = !a.no_chroma_detail;
  a.options.progress = !a.no_progress;
  if (!ParseSize(a.synth_size, &a.options.synth.width, &a.options.synth.height))
    return Fail(verb, "--synth-size '" + a.synth_size + "' is not WxH (1..32768 each)", kExitUsage);
  if (!a.shard.empty()) {
    a.options.shard = Shard::Parse(a.shard);
    if (!a.options.shard) return Fail(verb, "--shard '" + a.shard + "' is not I/N (1 <= I <= N <= 999)", kExitUsage);
  }
  if (std::string why = a.options.Check(); !why.empty()) return Fail(verb, why, kExitUsage);
  auto outcomes = RunProcess(a.options);
  if (!outcomes.ok()) return Fail(verb, outcomes.status());
  PrintProcessSummary(*outcomes);
  if (!a.outcome.empty())
    if (Status st = WriteJsonFile(a.outcome, OutcomesToJson(a.options.session, *outcomes)); !st.ok()) return Fail(verb, st);
  // One stage is a part of the whole: the session's report is written by a whole run (which,
  // after the workflow's stages, skips every one).
  if (!a.options.only_stage.empty()) return kExitOk;
  if (Status st = WriteProcessReport(a.options.session, *outcomes); !st.ok()) return Fail(verb, st);
  std::printf("process: done -> %s\n", SessionLayout(a.options.session).report_html().string().c_str());
  return kExitOk;
}
}  // namespace mesocap::app
