// What `synth`, `synth-apply` and `paint` write, one writer for all three: the map, the
// synthesized image / slices / PTM, previews under three lights, the patch picture and report.json,
// in a staging folder published whole (docs/formats.md, "Synthesis").
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/json.h"
#include "core/progress.h"
#include "core/session_layout.h"
#include "core/status.h"
#include "synth/exemplar.h"
#include "synth/synth_map.h"

namespace mesocap::app {

struct SynthOutputRequest {
  std::filesystem::path out;
  std::vector<int> slices;  // BTF: which exemplar slices to synthesize (empty: all)
  Json report;              // the method's own report; seams, timings and memory are added
  int num_threads = -1;
  bool replace = false;     // an existing `out` is swapped out whole (a re-run); else it must be empty
  // Files a method keeps beside its map (the texton analysis), written into the staging folder.
  std::function<Status(const std::filesystem::path& folder)> write_extra;
  // BTF: puts the requested slices into the staging folder and returns their index entries, in
  // order (a sharded stage's merge takes its shards' slices so); null: applies the map here.
  std::function<StatusOr<std::vector<Json>>(const std::filesystem::path& folder)> take_slices;
  // The report's "exemplar" figures (ExemplarReport); null: of the exemplar given.
  Json exemplar_report;
};

// The report's figures of an exemplar (its kind, size, slices, features).
Json ExemplarReport(const Exemplar& exemplar);

// Applies `map` to the BTF exemplar's `slices` on all cores, each written as a half-float slice
// into `folder` (its BtfFolder layout); their index entries in the order of `slices`.
// `on_slice` (may be null) sees each slice as made.
StatusOr<std::vector<Json>> WriteSynthesizedSlices(const SynthMap& map, const Exemplar& exemplar,
                                                   const std::vector<int>& slices, const std::filesystem::path& folder,
                                                   int num_threads, const ProgressFn& progress,
                                                   const std::function<void(int k, const Image& slice)>& on_slice = nullptr);

// Parses WxH ("512x512" or "512").
bool ParseSize(const std::string& text, int* width, int* height);
// Parses "all" or a comma-separated list of slice indices.
bool ParseSliceList(const std::string& text, int count, std::vector<int>* slices);

Status WriteSynthesisOutputs(const SynthMap& map, const Exemplar& exemplar, SynthOutputRequest request,
                             const ProgressFn& progress);

// What a synthesis folder's report.json says that other commands read (the report, the export).
struct SynthReportSummary {
  std::string method;
  int width = 0, height = 0;            // the output, texels
  int tile_width = 0, tile_height = 0;  // roller: its tile; 0 for the other methods and for a map synth-apply wrote
};
// The error names the file and the field.
StatusOr<SynthReportSummary> ReadSynthReportSummary(const SynthFolder& folder);

// Loads a 1-channel mask (white = 1) from any image; the error names the file.
StatusOr<Image> ReadMask(const std::filesystem::path& path);

}  // namespace mesocap::app
