// Test support: the lights each of the rig's views measures in the tests' idealised sessions.
// A hand-held flash stays on the camera's side, so the top view sees it from everywhere and a
// tilted view only from around its own direction.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/directions.h"
#include "core/image.h"
#include "reconstruct/btf_evaluation.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap::testing {

// How far from a tilted view's own direction the tests' flash reaches.
inline constexpr double kFlashReachDeg = 50;

// True when the rig's `view` measures `light`: the top view every light, a tilted one those within
// kFlashReachDeg of its direction.
inline bool RigViewMeasures(const Eigen::Vector3d& view, const Eigen::Vector3d& light) {
  return view.z() > 0.99 || AngleBetweenDeg(light, view) <= kFlashReachDeg;
}

using SliceFn = std::function<Image(const Eigen::Vector3d& light, const Eigen::Vector3d& view)>;

// The statistical BTF of `slice` as the rig measures it: its 13 views (RigViewDirections, the top
// one first) under the Bonn lights each measures, the top view's slices as the base. `options`
// take their colour channels from the top view's slices.
inline StatusOr<StatisticalBtf> ReconstructFromRigViews(const SliceFn& slice, StatisticalBtfOptions options) {
  const std::vector<Eigen::Vector3d> bonn = BonnDirections();
  std::vector<MeasuredView> measured;
  std::vector<Image> top;
  for (const Eigen::Vector3d& view : RigViewDirections()) {
    std::vector<Eigen::Vector3d> lights;
    std::vector<Image> slices;
    for (const Eigen::Vector3d& light : bonn)
      if (RigViewMeasures(view, light)) lights.push_back(light), slices.push_back(slice(light, view));
    if (view.z() > 0.99) top = slices, options = WithColourChannels(options, top);
    measured.push_back(MeasureView(view, lights, slices, options));
  }
  return StatisticalBtf::Create(top, bonn, std::move(measured), options);
}

}  // namespace mesocap::testing
