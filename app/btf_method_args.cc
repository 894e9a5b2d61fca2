#include "app/btf_method_args.h"

#include "core/session.h"

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
  if (!mirror_images.empty()) btf->mirror_images_allowed = MirrorImagesNamed(mirror_images);
  btf->far_light_falloff_deg = far_light_falloff_deg;
  return true;
}

bool BtfMethodArgs::ApplyTo(SliceSetOptions* slices) const {
  if (chroma_from_top || chroma_from_views) slices->chroma_from_top = chroma_from_top;
  slices->remove_chroma_noise = !keep_chroma_noise;
  slices->capture_blur_px = capture_blur_px;
  return ApplyTo(&slices->btf);
}

std::string BtfMethodArgs::TakeSessionMirrorImages(const std::filesystem::path& session) {
  if (!mirror_images.empty() || no_mirror_symmetry) return "";
  auto manifest = ReadJsonFile(SessionLayout(session).manifest());
  if (!manifest.ok() || !manifest->is_object()) return "";
  const Json named = manifest->value("mirror_images", Json::array());
  if (!named.is_array()) return "";
  std::string words;
  for (const Json& name : named)
    for (const char* known : kMirrorImageNames)
      if (name.is_string() && name.get<std::string>() == known) {
        mirror_images.push_back(known);
        words += (words.empty() ? "" : ", ") + std::string(known);
      }
  return words;
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
          {"mirror_images", mirror_images.empty() ? Json("any the check finds") : Json(mirror_images)},
          {"remove_chroma_noise", !keep_chroma_noise},
          {"capture_blur_px", capture_blur_px},
          {"fit_light_falloff", !no_fit_light_falloff},
          {"far_light_falloff_deg", far_light_falloff_deg}};
}

}  // namespace mesocap::app
