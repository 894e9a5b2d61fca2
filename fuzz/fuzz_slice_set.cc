// A session's slices/index.json through reconstruct/slice_set.h LoadStatisticalBtf, as
// `mesocap reconstruct` reads it: the index (core/slice_index.h) grouped by board, near-duplicate
// lights dropped, the slices read and reduced to statistics, the lights triangulated into the
// statistical BTF. The folder holds real slice files for the index to name
// (fuzz/slice_files.h); one thread, so every input runs the same way.
#include "fuzz/slice_files.h"
#include "reconstruct/slice_set.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto index = mesocap::fuzz::SliceFolder() / "index.json";
  mesocap::fuzz::WriteBytes(index, data, size);
  mesocap::fuzz::Run([&] {
    mesocap::SliceSetOptions options;
    options.btf.num_threads = 1;
    mesocap::SliceSetReport report;
    auto btf = mesocap::LoadStatisticalBtf(index, options, &report);
    mesocap::fuzz::Explain("LoadStatisticalBtf", btf.status());
  });
  return 0;
}
