#pragma once
// What a scene may hold and still be traced accurately: Embree works in single precision, so
// every surface must stay near the origin, and motions must be physical.

#include "fmcw/sim/scenario.hpp"

namespace fmcw::sim {

/// Farthest any body may be from the world origin at a frame time [m]: a float's step is
/// 1 mm there, 1/25 of the range noise of Table I.
constexpr double kMaxSceneExtent_m = 10000.0;
/// Fastest a body may move [m/s] and turn [rad/s] (10 turns a second).
constexpr double kMaxSpeed_mps = 1000.0;
constexpr double kMaxTurnRate_rps = 20.0 * M_PI;

/// Throws std::invalid_argument naming the scenario file and the body's key (ego.trajectory,
/// static[k], actors[k]) when at a frame time (and, with motion distortion, over the frame's
/// sweep) a body is farther than kMaxSceneExtent_m from the origin, moves faster than
/// kMaxSpeed_mps or turns faster than kMaxTurnRate_rps, or a frame time is not finite.
void check_scene_limits(const Scenario& s);

}  // namespace fmcw::sim
