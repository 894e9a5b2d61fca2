// A session's manifest (session.json) through core/session.h Session::Open, beside a valid
// two-line journal; then the queries later stages make of an opened session.
#include "core/session.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path root = [] {
    const auto dir = mesocap::fuzz::ScratchDir() / "session";
    std::filesystem::create_directories(dir);
    mesocap::fuzz::WriteText(
        mesocap::SessionLayout(dir).journal(),
        "{\"index\":1,\"kind\":\"shot\",\"file\":\"shots/shot_0001.jpg\",\"time_utc\":\"2026-01-01T12:00:00Z\","
        "\"settings\":{\"iso\":100},\"exif\":{\"Flash\":1},\"flags\":[],\"event\":\"shot\"}\n"
        "{\"index\":1,\"kind\":\"calib\",\"file\":\"calib/calib_0001.jpg\",\"event\":\"shot\"}\n");
    return dir;
  }();
  mesocap::fuzz::WriteBytes(mesocap::SessionLayout(root).manifest(), data, size);
  mesocap::fuzz::Run([&] {
    auto session = mesocap::Session::Open(root);
    mesocap::fuzz::Explain("Session::Open", session.status());
    if (!session.ok()) return;
    (void)session->NextIndex("shot");
    (void)session->ShotsOfKind("calib");
    (void)session->manifest().dump();
  });
  return 0;
}
