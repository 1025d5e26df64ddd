#pragma once
// Incremental clearance checks: bodies are added one by one, each new one checked against
// everything added before, at every frame time.

#include <array>
#include <string>
#include <vector>

#include "fmcw/sim/scenario_generator.hpp"

namespace fmcw::sim {

struct MeshAsset;

class ClearanceIndex {
 public:
  /// A footprint placed at one time: its corners in the world plane and a circle around them.
  struct Placed {
    std::array<Eigen::Vector2d, 4> corners;
    Eigen::Vector2d centre;
    double radius = 0.0;
  };

  explicit ClearanceIndex(std::vector<double> times_s);
  const std::vector<double>& times_s() const { return times_s_; }

  void add_fixed(const Footprint& body);
  /// The body at every time.
  std::vector<Placed> sweep(const Footprint& body) const;
  /// Smallest gap of a swept body to everything added; stops early once below stop_below.
  ClearanceResult probe(const std::vector<Placed>& path, const std::string& what, double stop_below) const;
  void add_moving(std::vector<Placed> path, const std::string& what);
  /// Smallest gap of a fixed body (at its pose) to the fixed bodies added.
  double gap_to_fixed(const Footprint& body) const;
  /// A body at time t.
  static Placed place(const Footprint& body, double t_s);

 private:
  static Eigen::AlignedBox2d bounds(const std::vector<Placed>& path);
  static double box_gap(const Eigen::AlignedBox2d& a, const Eigen::AlignedBox2d& b);


  std::vector<double> times_s_;
  std::vector<Placed> fixed_;
  std::vector<std::string> fixed_names_;
  std::vector<Eigen::AlignedBox2d> fixed_bounds_;
  std::vector<std::vector<Placed>> moving_;
  std::vector<Eigen::AlignedBox2d> moving_bounds_;
  std::vector<std::string> moving_names_;
};

/// The rest-pose footprint of a mesh's vertices below max_z_m (body frame, after T_body_asset).
Eigen::AlignedBox2d footprint_below(const MeshAsset& asset, const Eigen::Affine3d& T_body_asset, double max_z_m);

}  // namespace fmcw::sim
