// The statistical BTF's method choices, as the commands that reconstruct take them (reconstruct
// and evaluate as --colour-space, --no-top-view-prior...; process as --btf-colour-space...): one
// set of flags, one way to apply them and one provenance record.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/json.h"
#include "reconstruct/slice_set.h"
#include "reconstruct/statistical_btf.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct BtfMethodArgs {
  std::string colour_space = "chromaticity";  // reconstruct/colour.h, by name
  bool no_top_view_prior = false;             // StatisticalBtfOptions::top_view_prior
  bool no_fit_light_falloff = false;          // StatisticalBtfOptions::fit_light_falloff
  bool change_from_top = false;               // StatisticalBtfOptions::blend_change_from_top
  bool no_white_specular = false;             // StatisticalBtfOptions::white_specular_colour
  bool no_mean_model = false;                 // StatisticalBtfOptions::mean_model
  bool linear_from_top_view = false;          // StatisticalBtfOptions::view_blend_even_at_pole
  bool no_mirror_symmetry = false;            // StatisticalBtfOptions::mirror_symmetry
  std::vector<std::string> mirror_images;     // StatisticalBtfOptions::mirror_images_allowed; none: any
  bool keep_chroma_noise = false;             // SliceSetOptions::remove_chroma_noise (sessions' slices)
  double capture_blur_px = SliceSetOptions().capture_blur_px;  // SliceSetOptions::capture_blur_px
  // StatisticalBtfOptions::chromaticity_from_top_view: forced on, forced off, or (neither) decided by
  // the slices' shots (SliceSetOptions::chroma_from_top; off for true slices).
  bool chroma_from_top = false, chroma_from_views = false;
  bool chroma_mean_from_views = false;  // StatisticalBtfOptions::chromaticity_mean_from_views
  double far_light_falloff_deg = StatisticalBtfOptions().far_light_falloff_deg;

  // Adds the flags to `command`, each named `prefix` + its name ("--" or "--btf-").
  void AddTo(CLI::App* command, const std::string& prefix = "--");
  // Sets them on `btf`; false on an unknown colour space.
  bool ApplyTo(StatisticalBtfOptions* btf) const;
  // The same, for a session's slices: also sets SliceSetOptions::chroma_from_top.
  bool ApplyTo(SliceSetOptions* slices) const;
  // For provenance and stage cache keys.
  Json ToJson() const;
  // Without --mirror-images, the images the session's capture guidance was told hold (its
  // manifest's "mirror_images", as `capture --guide-images` records them); returns them ("" if
  // none) for a line on what was used.
  std::string TakeSessionMirrorImages(const std::filesystem::path& session);
};

}  // namespace mesocap::app
