#pragma once
// Road layouts for the scenario generator: lanes as dense centre lines, walking paths,
// crossings, parking bays and slots for static objects. Right-hand traffic, lanes 3.5 m wide.

#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

namespace fmcw::sim::gen {

using Vec2 = Eigen::Vector2d;

inline constexpr double kLaneWidth_m = 3.5;
inline constexpr double kParkingWidth_m = 2.5;
inline constexpr double kSidewalkWidth_m = 4.0;

/// A position and heading in the plane.
struct Pose2 {
  Vec2 p = Vec2::Zero();
  double yaw_rad = 0.0;
};

/// A vehicle (or cyclist) route: a dense centre line (points about 1 m apart) from where it
/// enters the layout to where it leaves.
struct Route {
  std::vector<Vec2> pts;
  double stop_s = -1.0;  ///< arc length of the stop line along pts; < 0: none
  std::string kind;      ///< straight, left, right, lane_change, exit_1, exit_2, exit_3, ramp
  bool outermost = false;  ///< starts in the outermost lane (cyclists ride there)
};

/// A straight walking line (either direction).
struct Walkway {
  Vec2 a, b;
};

/// A crossing: from a waiting point on one curb to the other side.
struct Crossing {
  Vec2 from, to;
};

struct Layout {
  std::string name;
  int lanes_per_direction = 1;
  bool urban = true;  ///< pedestrians, cyclists and parking; false: a highway
  std::vector<Route> routes;
  std::vector<Route> bike_routes;
  std::vector<Walkway> walkways;
  std::vector<Crossing> crossings;
  std::vector<Pose2> parking;      ///< bay centres, heading with the traffic beside them
  std::vector<Pose2> buildings;    ///< candidate centres (they are checked against the roads)
  std::vector<Pose2> trees;
  std::vector<Pose2> poles;        ///< +x of the pole points at the road
  std::vector<Pose2> signs;
  std::vector<Pose2> barriers;     ///< highway: rows along the median and both edges
  double lane_length_m = 0.0;      ///< total length of the driving lanes
  double sidewalk_length_m = 0.0;
  double extent_m = 0.0;           ///< every route lies within this distance of the origin
};

/// Builds a layout by name: straight_road, junction, t_junction, roundabout, highway.
/// straight_lanes: lanes per direction of the straight road (others choose their own).
Layout make_layout(const std::string& name, int straight_lanes, bool parking, std::mt19937_64& rng);

/// The layout names, in documentation order.
const std::vector<std::string>& layout_names();

double uniform(std::mt19937_64& rng, double lo, double hi);
int uniform_int(std::mt19937_64& rng, int lo, int hi);  ///< lo..hi inclusive

/// Cumulative arc length of a polyline.
std::vector<double> arc_lengths(const std::vector<Vec2>& pts);
/// Unsigned curvature at each point from its neighbours about 2 m either side [1/m].
std::vector<double> curvatures(const std::vector<Vec2>& pts, const std::vector<double>& s);
/// Point and index at arc length s (linear between points).
Vec2 point_at(const std::vector<Vec2>& pts, const std::vector<double>& s, double at);

}  // namespace fmcw::sim::gen
