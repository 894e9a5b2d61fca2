// Flash power per shot from diffuse grey cards beside the target (Ngan & Durand section 2):
// the card's radiance, corrected for inverse-square distance and the cosine law, gives the
// power; a shadowed card falls back to the other cards, or to the mean power.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/camera_model.h"
#include "core/image.h"
#include "core/json.h"

namespace mesocap {

struct GreyCard {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // X_cam = R X_card + t, normal = R.col(2)
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double size_m = 0;  // side of the grey area, centred on the (tagged) mount
  double albedo = 0;
  Json ToJson() const;
};

struct CardReading {
  double power_x_exposure = 0;  // the card's estimate
  double variation = 0;         // coefficient of variation over the card: a shadow edge shows
  bool usable = false;
  std::string why_not;
};

// The card estimates for one shot with the flash at `light_m`.
std::vector<CardReading> ReadGreyCards(const CameraModel& camera, const std::vector<GreyCard>& cards,
                                       const Image& shot, const Eigen::Vector3d& light_m);

// Combines the readings of all shots: per shot the highest consistent card (a shadow only ever
// lowers a card), the mean power where every card was shadowed. Returns power x exposure per
// shot and sets `flags[s]` where the mean was used.
std::vector<double> CombineCardReadings(const std::vector<std::vector<CardReading>>& readings,
                                        std::vector<std::string>* flags);

}  // namespace mesocap
