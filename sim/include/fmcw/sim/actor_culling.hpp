#pragma once
// Where in a head's raster an actor can show up: the simulator traces only those beams against
// the actors (most beams pass far from every actor).

#include <Eigen/Geometry>
#include <vector>

#include "fmcw/core/head_model.hpp"
#include "fmcw/sim/scene.hpp"

namespace fmcw::sim {

/// The beams of one head that may reach one actor, as a rectangle of the image, and how near
/// the actor can be.
struct ActorFootprint {
  int row_begin = 0, row_end = 0;  ///< rows [row_begin, row_end)
  int col_begin = 0, col_end = 0;  ///< image columns [col_begin, col_end)
  double nearest_m = 0.0;          ///< no point of the actor is nearer to the head's origin
};

/// The footprints of the actors' bounding spheres seen from a head whose first image column is
/// col_begin, mounted at T_world_head: every beam whose direction lies within margin_rad of
/// the cone from the origin around a sphere, padded by a pixel on each side. Actors beyond the
/// head's range or outside its field of view get none.
void actor_footprints(const std::vector<BoundingSphere>& bounds, const core::HeadModel& head, int col_begin,
                      const Eigen::Isometry3d& T_world_head, double margin_rad, std::vector<ActorFootprint>& out);

/// How near the nearest actor whose footprint overlaps rows [r0, r1) x columns [c0, c1) can
/// be; +inf when no footprint does.
double nearest_actor_m(const std::vector<ActorFootprint>& footprints, int r0, int r1, int c0, int c1);

}  // namespace fmcw::sim
