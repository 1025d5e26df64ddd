#pragma once
// Analytic frames with known answers for evaluation tests: a rigidly translating box seen by the
// paper's rig from an ego driving at 8 m/s, without noise, with the frame truth filled in.

#include <string>

#include "fmcw/core/synthetic_scan.hpp"
#include "fmcw/eval/frame_source.hpp"

namespace fmcw::test {

/// Frame k (at 0.1 k s): the box 25 - 0.6 k m ahead, 3 m to the left, moving at -6 m/s along x.
inline core::Frame synthetic_frame(std::size_t k) {
  core::SyntheticSceneParams p;
  p.ego_velocity_mps = Eigen::Vector3d(8.0, 0.0, 0.0);
  core::SyntheticBox wall;
  wall.center_m = Eigen::Vector3d(60.0, 0.0, 5.0);
  wall.half_extent_m = Eigen::Vector3d(0.5, 80.0, 5.0);
  p.static_boxes.push_back(wall);
  core::SyntheticBox car;
  car.center_m = Eigen::Vector3d(25.0 - 0.6 * static_cast<double>(k), 3.0, 0.9);
  car.half_extent_m = Eigen::Vector3d(2.2, 0.9, 0.75);
  car.velocity_mps = Eigen::Vector3d(-6.0, 0.0, 0.0);
  p.actors.push_back(car);
  core::Frame f = core::render_synthetic_scan(p);
  core::FrameTruth t;
  t.stamp_s = 0.1 * static_cast<double>(k);
  f.scan.stamp_s = t.stamp_s;  // a tracker resets on a stamp that does not advance
  t.ego.velocity_mps = p.ego_velocity_mps;
  core::ActorTruth a;
  a.id = 1;
  a.class_name = "car";
  a.position_rig_m = car.center_m;
  a.velocity_rig_mps = car.velocity_mps;
  t.actors.push_back(a);
  f.frame_truth = t;
  return f;
}

/// synthetic_frame(0 .. frames - 1) as a FrameSource.
class SyntheticSource : public eval::FrameSource {
 public:
  explicit SyntheticSource(std::size_t frames) : frames_(frames) {
    info_.scenario = "synthetic";
    info_.path = "memory";
  }
  std::size_t size() const override { return frames_; }
  core::Frame frame(std::size_t k) override { return synthetic_frame(k); }
  std::string describe(std::size_t k) const override { return "synthetic frame " + std::to_string(k); }
  const eval::SourceInfo& info() const override { return info_; }

 private:
  std::size_t frames_;
  eval::SourceInfo info_;
};

}  // namespace fmcw::test
