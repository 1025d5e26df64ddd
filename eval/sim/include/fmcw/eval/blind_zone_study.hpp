#pragma once
// `fmcw study blind-zone`: detection recall of one moving actor against its heading relative
// to the beam, for several speeds and distances, beside the blind band of Eq. 15.

#include <functional>
#include <string>
#include <vector>

#include "fmcw/eval/band_edges.hpp"
#include "fmcw/eval/blind_zone_scene.hpp"

namespace fmcw::eval {

/// An actor shape swept at some distances.
struct BlindZoneTarget {
  std::string name;
  Eigen::Vector3d box_size_m = Eigen::Vector3d(4.5, 1.8, 1.5);  ///< length, width, height [m]
  std::vector<double> distances_m;                              ///< [m]
  std::string mesh;  ///< a mesh file instead of the box (assets/car.gltf, ...); empty = the box
};

struct BlindZoneStudyParams {
  std::vector<double> speeds_mps = {1.0, 2.0, 5.0, 10.0, 25.0};
  /// A car-sized box at 10, 20 and 40 m (what traffic looks like), and a small box far away: the
  /// closest this rig gets to the point target Eq. 15 reasons about.
  std::vector<BlindZoneTarget> targets = {{"car_box", Eigen::Vector3d(4.5, 1.8, 1.5), {10.0, 20.0, 40.0}, ""},
                                          {"small_box", Eigen::Vector3d(0.5, 0.5, 0.5), {40.0}, ""}};
  double phi_step_deg = 1.0;  ///< coarse sweep over [phi_min, phi_max] [deg]
  double phi_min_deg = 0.0;
  double phi_max_deg = 180.0;
  /// Extra samples at this step within fine_margin_deg of the theoretical band, for bands too
  /// narrow for the coarse sweep (they are added when the band is under 4 coarse steps wide) [deg].
  double fine_step_deg = 0.1;
  double fine_margin_deg = 1.0;
  /// Bisection steps on each measured band edge (each halves the bracket) after the sweeps.
  int refine_iterations = 6;
  double recall_level = 0.5;  ///< a band edge is where recall crosses this level
  double velocity_threshold_mps = 0.17;  ///< v_th of the methods and of Eq. 15 [m/s]
  bool noise_free_too = true;  ///< also evaluate each frame with its noise-free Doppler
  std::vector<std::string> methods;  ///< preset names; empty = all ("paper" first)
  BlindZoneSceneParams scene;  ///< box_size_m and the mesh are set per target

  void validate() const;
};

/// One simulated sample: a heading, evaluated by each method with and without noise.
struct BlindZoneSample {
  std::string target;
  double speed_mps = 0.0;
  double distance_m = 0.0;
  double phi_deg = 0.0;
  int object_pixels = 0;  ///< valid pixels on the actor
  /// Smallest |true Doppler| over the actor's pixels that touch the static world (8-neighbours):
  /// Eq. 15 applied at the silhouette, where region growing would join the two [m/s].
  double silhouette_min_doppler_mps = 0.0;
  std::vector<double> recall;             ///< [method], with Table I noise
  std::vector<double> recall_noise_free;  ///< [method], Doppler without noise (empty when off)
};

/// Band edges of one (speed, distance, method, noise) curve, with the two predictions.
struct BlindZoneBand {
  std::string target;
  double speed_mps = 0.0;
  double distance_m = 0.0;
  std::string method;
  bool noise = true;         ///< Table I noise (true) or noise-free Doppler
  BandEdges measured;        ///< from the recall curve
  BandEdges theory;          ///< Eq. 15 at the beam towards the centre
  BandEdges silhouette;      ///< Eq. 15 at the actor's silhouette (silhouette_min_doppler < v_th)
};

struct BlindZoneStudyResult {
  BlindZoneStudyParams params;
  std::vector<std::string> methods;
  std::vector<BlindZoneSample> samples;  ///< sorted by speed, distance, phi
  std::vector<BlindZoneBand> bands;
  double seconds = 0.0;
};

/// progress(done, total) after each (target, speed, distance).
BlindZoneStudyResult run_blind_zone_study(const BlindZoneStudyParams& params,
                                          const std::function<void(int, int)>& progress = {});

/// blind_zone_samples.csv, blind_zone_bands.csv, then metrics.json (kind "blind_zone").
void write_blind_zone_report(const std::string& dir, const BlindZoneStudyResult& result,
                             const std::string& tool_version);

}  // namespace fmcw::eval
