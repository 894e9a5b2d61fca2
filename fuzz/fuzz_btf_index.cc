// A BTF folder's index.json (format mesocap-btf or mesocap-slices) through synth/exemplar.h
// LoadExemplar, as `mesocap synth --input DIR/index.json` reads it: the index is parsed and
// checked, then the slices it names are read and reduced to features. Real slice files are
// provided (fuzz/slice_files.h); few SVD components and one thread keep each run short.
#include "fuzz/slice_files.h"
#include "synth/exemplar.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto index = mesocap::fuzz::SliceFolder() / "index.json";
  mesocap::fuzz::WriteBytes(index, data, size);
  mesocap::fuzz::Run([&] {
    mesocap::ExemplarOptions options;
    options.svd_components = 4;
    options.num_threads = 1;
    auto exemplar = mesocap::LoadExemplar(index, options);
    mesocap::fuzz::Explain("LoadExemplar", exemplar.status());
  });
  return 0;
}
