#include "calib/flash_power.h"


#include <algorithm>
#include <cmath>
#include <numbers>

namespace mesocap {

Json GreyCard::ToJson() const {
  return {{"R", mesocap::ToJson(R)}, {"t", mesocap::ToJson(t)}, {"size_m", size_m}, {"albedo", albedo}};
}

std::vector<CardReading> ReadGreyCards(const CameraModel& camera, const std::vector<GreyCard>& cards, const Image& shot,
                                       const Eigen::Vector3d& light_m) {
  std::vector<CardReading> out;
  for (const GreyCard& card : cards) {
    CardReading r;
    // Sample the inner 60% of the card densely; compare 4x4 block means, so that sensor noise
    // averages out and only a shadow edge makes the blocks differ.
    const int n = 48, blocks = 4;
    std::vector<double> block_sum(blocks * blocks, 0.0);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double u = (-0.3 + 0.6 * (i + 0.5) / n) * card.size_m, v = (-0.3 + 0.6 * (j + 0.5) / n) * card.size_m;
        const Eigen::Vector2d px = camera.Project(card.R * Eigen::Vector3d(u, v, 0) + card.t);
        float p[4] = {0, 0, 0, 0};
        shot.SampleBilinear(float(px.x() + 0.5), float(px.y() + 0.5), p);
        block_sum[(j * blocks / n) * blocks + i * blocks / n] += shot.channels() >= 3 ? (p[0] + p[1] + p[2]) / 3 : p[0];
      }
    double mean = 0, sq = 0;
    for (double& b : block_sum) mean += (b /= double(n * n) / (blocks * blocks));
    mean /= block_sum.size();
    for (double b : block_sum) sq += (b - mean) * (b - mean);
    r.variation = mean > 0 ? std::sqrt(sq / block_sum.size()) / mean : 1.0;
    const Eigen::Vector3d to_light = light_m - card.t;
    const double d2 = to_light.squaredNorm();
    const double cos_i = card.R.col(2).dot(to_light.normalized());
    if (cos_i < 0.15) {
      r.why_not = "flash grazes the card";
    } else if (mean <= 0 || mean >= 0.98) {
      r.why_not = mean <= 0 ? "card black" : "card saturated";
    } else if (r.variation > 0.05) {
      r.why_not = "card partly shadowed";
    } else {
      r.usable = true;
      r.power_x_exposure = mean * std::numbers::pi * d2 / (card.albedo * cos_i);
    }
    out.push_back(r);
  }
  return out;
}

std::vector<double> CombineCardReadings(const std::vector<std::vector<CardReading>>& readings,
                                        std::vector<std::string>* flags) {
  std::vector<double> power(readings.size(), 0);
  flags->assign(readings.size(), "");
  double sum = 0;
  int n = 0;
  for (size_t s = 0; s < readings.size(); ++s) {
    double best = 0;
    for (const auto& r : readings[s])
      if (r.usable) best = std::max(best, r.power_x_exposure);
    // A card wholly inside a ball's shadow is uniform but dark: trust the brightest card, and a
    // lone card only when no other card contradicts it.
    power[s] = best;
    if (best > 0) {
      sum += best;
      ++n;
    }
  }
  const double mean = n ? sum / n : 0;
  for (size_t s = 0; s < readings.size(); ++s) {
    if (power[s] > 0 && power[s] > 0.6 * mean) continue;
    (*flags)[s] = power[s] > 0 ? "every card shadowed (reading far below the mean): mean power used"
                               : "no usable grey card: mean power used";
    power[s] = mean;
  }
  return power;
}

}  // namespace mesocap
