// A session's journal (journal.jsonl) through core/session.h Session::Open, beside a valid
// manifest; then the queries capture and calibration make of the replayed shots.
#include "core/session.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path root = [] {
    const auto dir = mesocap::fuzz::ScratchDir() / "session";
    std::filesystem::create_directories(dir);
    mesocap::fuzz::WriteText(mesocap::SessionLayout(dir).manifest(),
                             "{\"format\":\"mesocap-session\",\"format_version\":1,\"source\":\"virtual\"}\n");
    return dir;
  }();
  mesocap::fuzz::WriteBytes(mesocap::SessionLayout(root).journal(), data, size);
  mesocap::fuzz::Run([&] {
    auto session = mesocap::Session::Open(root);
    mesocap::fuzz::Explain("Session::Open", session.status());
    if (!session.ok()) return;
    (void)session->NextIndex("shot");
    (void)session->NextIndex("calib");
    for (const auto& shot : session->ShotsOfKind("shot")) (void)shot.ToJson().dump();
    (void)session->torn_journal_lines();
  });
  return 0;
}
