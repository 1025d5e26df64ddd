#pragma once
// Where a detection-recall curve dips into the Doppler blind band (Eq. 15) and comes out again.

#include <vector>

namespace fmcw::eval {

/// Edges of a blind band [deg]. found is false when no sample lies below the level; an edge is
/// NaN when the band reaches the end of the sampled range on that side.
struct BandEdges {
  bool found = false;
  double lower_deg = 0.0;
  double upper_deg = 0.0;
};

/// The blind band of a recall curve sampled at angles phi_deg (any order; sorted internally):
/// the run of consecutive samples below level that contains the sample nearest to centre_deg,
/// or else the run closest to it. Each edge is the linear interpolation of the level crossing
/// between the run's outermost sample and its neighbour outside the run. Throws
/// std::invalid_argument when the arrays differ in size or hold non-finite values.
BandEdges find_blind_band(const std::vector<double>& phi_deg, const std::vector<double>& recall, double level = 0.5,
                          double centre_deg = 90.0);

/// Eq. 15: an object moving at speed v is not separated from the static world when
/// |v cos phi| < v_th; the band is (acos(v_th / v), 180 - acos(v_th / v)) [deg]. For v <= v_th
/// every heading is blind: (0, 180).
BandEdges theoretical_blind_band(double speed_mps, double velocity_threshold_mps);

}  // namespace fmcw::eval
