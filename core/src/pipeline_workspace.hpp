#pragma once
// Internal to core: the buffers a MotionPipeline keeps from frame to frame (PipelineBuffers).

#include "ego_twist_beams.hpp"
#include "scan_beams.hpp"

namespace fmcw::core {

struct PipelineWorkspace {
  ScanBeams beams;
  EgoTwistWorkspace ego;
};

}  // namespace fmcw::core
