#include "app/btf_method_args.h"

namespace mesocap::app {

bool BtfMethodArgs::ApplyTo(StatisticalBtfOptions* btf) const {
  const std::optional<ColourSpace> space = ParseColourSpace(colour_space);
  if (!space) return false;
  btf->colour_space = *space;
  btf->top_view_prior = !no_top_view_prior;
  btf->fit_light_falloff = !no_fit_light_falloff;
  btf->blend_change_from_top = change_from_top;
  btf->chromaticity_from_top_view = chroma_from_top;
  btf->chromaticity_mean_from_views = chroma_mean_from_views;
  btf->white_specular_colour = !no_white_specular;
  btf->mean_model = !no_mean_model;
  btf->view_blend_even_at_pole = !linear_from_top_view;
  btf->mirror_symmetry = !no_mirror_symmetry;
  btf->far_light_falloff_deg = far_light_falloff_deg;
  return true;
}

bool BtfMethodArgs::ApplyTo(SliceSetOptions* slices) const {
  if (chroma_from_top || chroma_from_views) slices->chroma_from_top = chroma_from_top;
  slices->remove_chroma_noise = !keep_chroma_noise;
  slices->capture_blur_px = capture_blur_px;
  return ApplyTo(&slices->btf);
}

Json BtfMethodArgs::ToJson() const {
  return {{"colour_space", colour_space},
          {"top_view_prior", !no_top_view_prior},
          {"change_from_top", change_from_top},
          {"chroma_from_top", chroma_from_top ? "on" : chroma_from_views ? "off" : "by the shots"},
          {"chroma_mean_from_views", chroma_mean_from_views},
          {"white_specular_colour", !no_white_specular},
          {"mean_model", !no_mean_model},
          {"view_blend_even_at_pole", !linear_from_top_view},
          {"mirror_symmetry", !no_mirror_symmetry},
          {"remove_chroma_noise", !keep_chroma_noise},
          {"capture_blur_px", capture_blur_px},
          {"fit_light_falloff", !no_fit_light_falloff},
          {"far_light_falloff_deg", far_light_falloff_deg}};
}

}  // namespace mesocap::app
