// BtfMethodArgs::AddTo, on its own: the front executable (app/main.cc) defines the flags; the
// commands module applies them (btf_method_args.cc).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/btf_method_args.h"

namespace mesocap::app {

void BtfMethodArgs::AddTo(CLI::App* command, const std::string& prefix) {
  std::vector<std::string> names;
  for (ColourSpace space : kColourSpaces) names.push_back(ColourSpaceName(space));
  command
      ->add_option(prefix + "colour-space", colour_space,
                   "Colour channels histograms are matched in: chromaticity (brightness and r, g chromaticities: "
                   "keeps colours true), pca (the top view's principal colour axes) or rgb (each on its own, as the paper)")
      ->check(CLI::IsMember(names))
      ->capture_default_str();
  command->add_flag(prefix + "no-top-view-prior", no_top_view_prior,
                    "For lights beyond a view's measured lights, hold the statistics of their edge (the paper) instead "
                    "of moving them by the top view's change in light");
  command->add_flag(prefix + "change-from-top", change_from_top,
                    "Inside a view's measured lights, blend its change from the top view and add the top view's "
                    "statistics at the light, instead of blending its statistics as measured (the paper)");
  CLI::Option* from_top = command->add_flag(
      prefix + "chroma-from-top", chroma_from_top,
      "Take the chromaticity's statistics from the top view at the light instead of blending the views' (default for "
      "slices of JPEG shots, whose colour is at half resolution: the tilted boards' patches span the fewest pixels)");
  CLI::Option* from_views =
      command
          ->add_flag(prefix + "chroma-from-views", chroma_from_views,
                     "Blend the views' own chromaticity statistics (the paper; default for slices of RAW, PNG or TIFF "
                     "shots and for true slices)")
          ->excludes(from_top);
  command
      ->add_flag(prefix + "chroma-mean-from-views", chroma_mean_from_views,
                 "With the top view's chromaticity (JPEG shots, or --chroma-from-top): shift its histograms by the "
                 "views' mean colour's chromaticity less its own (off: on calibrated sessions it helps corduroy's "
                 "colour and costs stones')")
      ->excludes(from_views);
  command->add_flag(prefix + "no-white-specular", no_white_specular,
                    "Keep the blended statistics' colour instead of moving it toward white by a white specular lobe "
                    "fitted to the measured slices' mean colours (the whitening near a view's mirror direction)");
  command->add_flag(prefix + "no-mean-model", no_mean_model,
                    "Keep the blended statistics' mean brightness where a light lies beyond the measured lights, instead of "
                    "scaling to a model of the mean fitted to every measured slice (used only if it predicts each tilted "
                    "view's slices, fitted without them, better than the top view does)");
  command->add_flag(prefix + "keep-chroma-noise", keep_chroma_noise,
                    "Keep each session slice's noise in its chromaticity statistics instead of taking out the variance "
                    "measured against the slice of the same view at the nearest light");
  command->add_option(prefix + "capture-blur-px", capture_blur_px,
                      "Undo a Gaussian blur of this many camera pixels (the camera's and the resampling's) on each "
                      "session slice's chromaticities before their statistics, in texels from the slice's size in "
                      "the photo (0: keep the blur)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  command->add_flag(prefix + "linear-from-top-view", linear_from_top_view,
                    "Interpolate a view between the top view and the first view ring linearly in incidence (the "
                    "paper) instead of in 1 - cos(incidence), in which statistics even through the pole change linearly");
  command->add_flag(prefix + "no-mirror-symmetry", no_mirror_symmetry,
                    "Use each view's own measured lights only, instead of also its images' under the symmetries of the "
                    "square (mirrors, half and quarter turns) wherever the top view's own slices show the material looks "
                    "the same imaged");
  const std::vector<std::string> image_names(kMirrorImageNames.begin(), kMirrorImageNames.end());
  command->add_option(prefix + "mirror-images", mirror_images,
                      "The images of the patch the material is known to look the same under (comma-separated, as "
                      "`capture --guide-images` names them): the symmetry check may find only these. Default: any. "
                      "From a session's few or spread-out top-view lights the check can pass a wrong one")
      ->delimiter(',')
      ->check(CLI::IsMember(image_names));
  command->add_flag(prefix + "no-fit-light-falloff", no_fit_light_falloff,
                    "Blend neighbouring lights on plain cos(theta_i) ratios instead of raising them to the exponent "
                    "fitted to the top view's mean radiance against cos(theta_i)");
  command
      ->add_option(prefix + "far-light-falloff", far_light_falloff_deg,
                   "With the top-view prior: past 15 deg from a view's nearest measured light, its own change from the top "
                   "view fades with this scale in degrees (0: carried whole)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 180.0));
}

}  // namespace mesocap::app
