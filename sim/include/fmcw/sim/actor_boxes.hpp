#pragma once
// The ground-truth box of every actor: an oriented box tight around its surface at the frame's
// instant, heading along its body, with the velocity of its centre and what the rig sees of it.

#include <Eigen/Geometry>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/head_model.hpp"
#include "fmcw/sim/scene.hpp"

namespace fmcw::sim {

/// Fills actors[k].box for actor k of the scene at its current time, seen from the rig at
/// T_world_rig (rig.directions_rig() per pixel in directions_rig): the box in the rig and world
/// frames, the velocity of its centre (the body's rigid motion there), truncated when a corner
/// lies outside every head's field of view, and visible_fraction = actors[k].pixels over the
/// pixels whose beams meet the box between min_range_m and the head's range. Actors are shared
/// out over num_threads threads; the result does not depend on it.
void actor_boxes(const Scene& scene, const core::RigModel& rig, const std::vector<Eigen::Vector3f>& directions_rig,
                 const Eigen::Isometry3d& T_world_rig, double min_range_m, int num_threads,
                 std::vector<core::ActorTruth>& actors);

}  // namespace fmcw::sim
