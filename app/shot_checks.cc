#include "app/shot_checks.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "app/rig_plot.h"
#include "calib/flash_power.h"
#include "calib/resample.h"
#include "core/text_format.h"

namespace mesocap::app {
namespace {

const LayoutBoard* LayoutOfBoard(const RigLayout& layout, int id) {
  for (const LayoutBoard& b : layout.boards)
    if (b.id == id) return &b;
  return nullptr;
}

double Percentile(std::vector<float> values, double q) {
  if (values.empty()) return 0;
  const size_t k = std::min(values.size() - 1, size_t(q * double(values.size() - 1)));
  std::nth_element(values.begin(), values.begin() + long(k), values.end());
  return values[k];
}

}  // namespace

double TopBoardSharpness(const Image& shot, const CalibrationResult& rig, const RigLayout& layout) {
  const BoardPose* top = TopBoardPose(rig);
  const LayoutBoard* board = top ? LayoutOfBoard(layout, top->id) : nullptr;
  if (!board || !top->found) return 0;
  constexpr int kTexels = 256;
  const PatchSampler sampler = MakePatchSampler(rig.camera, *top, board->size_m, kTexels);
  // Lit from the camera's side: only the shape of the edges matters, not the irradiance.
  const Image view = ResamplePatch(shot, sampler, Eigen::Vector3d(0, 0, 1), 1.0);
  std::vector<float> luminance(size_t(kTexels) * kTexels), gradient;
  for (int y = 0; y < kTexels; ++y)
    for (int x = 0; x < kTexels; ++x)
      luminance[size_t(y) * kTexels + x] = (view.at(x, y, 0) + view.at(x, y, 1) + view.at(x, y, 2)) / 3;
  const auto L = [&](int x, int y) { return luminance[size_t(y) * kTexels + x]; };
  for (int y = 1; y + 1 < kTexels; ++y)
    for (int x = 1; x + 1 < kTexels; ++x)
      gradient.push_back(std::hypot(L(x + 1, y) - L(x - 1, y), L(x, y + 1) - L(x, y - 1)) / 2);
  const double contrast = Percentile(luminance, 0.98) - Percentile(luminance, 0.02);
  if (!(contrast > 0)) return 0;
  std::sort(gradient.begin(), gradient.end(), std::greater<float>());
  const size_t strongest = std::max<size_t>(1, gradient.size() / 10);
  double sum = 0;
  for (size_t i = 0; i < strongest; ++i) sum += gradient[i];
  return sum / double(strongest) / contrast;
}

std::vector<std::string> CheckShot(const Image& shot, const CalibrationResult& rig, const RigLayout& layout,
                                   const std::optional<Eigen::Vector3d>& flash, const std::vector<double>& earlier_sharpness,
                                   double sharpness, const ShotCheckOptions& options) {
  std::vector<std::string> warnings;
  std::string overexposed;
  for (const BoardPose& pose : rig.boards) {
    const LayoutBoard* board = LayoutOfBoard(layout, pose.id);
    if (!pose.found || !board) continue;
    const PatchSampler sampler = MakePatchSampler(rig.camera, pose, board->patch_m, 64);
    int saturated = 0;
    ResamplePatch(shot, sampler, Eigen::Vector3d(0, 0, 1), 1.0, options.saturation_level, &saturated);
    const double fraction = double(saturated) / (64.0 * 64.0);
    if (fraction > options.max_saturated_fraction)
      overexposed += Format("%sboard %d %.0f%%", overexposed.empty() ? "" : ", ", pose.id, 100 * fraction);
  }
  if (!overexposed.empty())
    warnings.push_back("overexposed patches, their slices are left out (hold the flash farther away or lower its "
                       "power): " + overexposed);
  if (flash && !rig.grey_cards.empty()) {
    std::set<std::string> reasons;
    bool usable = false;
    for (const CardReading& card : ReadGreyCards(rig.camera, rig.grey_cards, shot, *flash)) {
      usable |= card.usable;
      if (!card.usable) reasons.insert(card.why_not);
    }
    std::string why;
    for (const std::string& r : reasons) why += (why.empty() ? "" : ", ") + r;
    if (!usable) warnings.push_back("no grey card to read the flash's power from (" + why + "): the session's mean power is used");
  }
  if (int(earlier_sharpness.size()) >= options.sharpness_baseline_shots && sharpness > 0) {
    std::vector<double> sorted = earlier_sharpness;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    if (sharpness < options.min_sharpness_ratio * median)
      warnings.push_back(Format("blurred: the boards' edges are %.0f%% as sharp as in the session's other shots "
                                "(camera shake, or focus lost)", 100 * sharpness / median));
  }
  return warnings;
}

}  // namespace mesocap::app
