// Embeds the installed core: builds an organized scan of a static world from arrays, as a driver
// would, with the Doppler a rig moving at a known velocity measures (Eq. 6: v = e . (V_point -
// V_rig), V_point = 0), runs MotionPipeline on it and checks the ego velocity it returns.
// With fmcw::io, the scan also goes through a PCD file and back first.

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/core/scan.hpp"
#ifdef FMCW_CONSUMER_IO
#include "fmcw/io/pcd.hpp"
#endif

int main(int argc, char** argv) {
  const Eigen::Vector3d ego_mps(8.0, -0.5, 0.2);  // the rig's velocity, rig axes
  const int rows = 40, cols = 120;
  fmcw::core::Scan scan = fmcw::core::Scan::make_empty(rows, cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      // A beam fan of 60 deg x 20 deg onto a wall 20 m ahead and the ground 2 m below.
      const double az = (30.0 - 0.5 * c) * M_PI / 180.0, el = (10.0 - 0.5 * r) * M_PI / 180.0;
      const Eigen::Vector3d e(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      double t = 20.0 / e.x();
      if (e.z() < 0.0) t = std::min(t, -2.0 / e.z());
      const Eigen::Vector3d p = t * e;
      const std::size_t i = scan.index(r, c);
      scan.x_m[i] = static_cast<float>(p.x());
      scan.y_m[i] = static_cast<float>(p.y());
      scan.z_m[i] = static_cast<float>(p.z());
      scan.range_m[i] = static_cast<float>(t);
      scan.radial_velocity_mps[i] = static_cast<float>(e.dot(-ego_mps));  // static world
      scan.intensity[i] = 1.0f;
      scan.valid[i] = 1;
    }
  }
#ifdef FMCW_CONSUMER_IO
  const std::string path = (std::filesystem::path(argc > 1 ? argv[1] : ".") / "consumer_scan.pcd").string();
  fmcw::core::Frame frame;
  frame.scan = scan;
  fmcw::io::write_frame(path, frame, false);
  scan = fmcw::io::read_frame(path).scan;
#else
  (void)argc;
  (void)argv;
#endif
  fmcw::core::MotionPipeline pipeline;
  const fmcw::core::MotionEstimate est = pipeline.process(scan);
  const Eigen::Vector3d v = est.ego.velocity_mps;
  std::printf("method %s, status %s, ego (%.4f, %.4f, %.4f) m/s, expected (%.1f, %.1f, %.1f)\n", est.method.c_str(),
              fmcw::core::to_string(est.status).c_str(), v.x(), v.y(), v.z(), ego_mps.x(), ego_mps.y(), ego_mps.z());
  // float Doppler: the least-squares answer is exact to float rounding.
  if (!est.ok() || !((v - ego_mps).norm() < 1e-3)) {
    std::printf("FAILED: the ego velocity is off by %.6f m/s\n", (v - ego_mps).norm());
    return 1;
  }
  return 0;
}
