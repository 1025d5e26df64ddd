#pragma once
// OpenPCDet's custom-dataset layout (its docs/CUSTOM_DATASET_TUTORIAL.md) from a dataset's frames
// and objects.csv boxes, all in the rig frame (x forward, y left, z up, as OpenPCDet's own):
//   points/ID.npy        float32 (N, 5): x y z intensity v of the points with a return
//   labels/ID.txt        one line per actor with at least one pixel:
//                        x y z dx dy dz heading class_name (box centre, length width height, yaw)
//   ImageSets/train.txt  the frame ids, one a line
//   meta.json            what the label lines cannot carry: the class list and, per frame and box
//                        (in label line order), actor id, box velocity, visible_fraction, truncated
// docs/FORMATS.md ("OpenPCDet") documents every column.

#include <string>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/io/pcd.hpp"

namespace fmcw::io {

/// The actors of a frame that get a box: those with at least one pixel, in objects.csv order.
std::vector<const core::ActorTruth*> openpcdet_boxes(const core::FrameTruth& truth);

/// The text of a frame's label file, one line per box of openpcdet_boxes, single spaces between
/// columns (OpenPCDet splits at ' '). std::invalid_argument naming where for a class name that is
/// empty or holds white space, or a box value that is not finite.
std::string openpcdet_labels(const core::FrameTruth& truth, const std::string& where);

/// Writes a frame's points (.npy) and labels (.txt), each atomically; the points are removed
/// again when the labels cannot be written. Returns the number of points. std::invalid_argument
/// naming where for a cloud without x y z or v, a point with a return whose intensity or v is not
/// finite, or labels openpcdet_labels refuses (checked before anything is written). A cloud
/// without `intensity` gets 0 there.
std::size_t write_openpcdet_frame(const std::string& points_path, const std::string& labels_path, const PcdCloud& cloud,
                                  const core::FrameTruth& truth, const std::string& where);

/// ImageSets/train.txt: the frame ids, one a line, atomically.
void write_openpcdet_split(const std::string& path, const std::vector<std::string>& frame_ids);

/// meta.json, atomically: frame_ids[k] names frame k of truth (the frame of objects.csv); source
/// is the dataset it came from. The class list holds the actor classes of the whole table in
/// first-seen order (rows of objects.csv), visible or not, so that it is the same for any
/// subset of the frames' boxes.
void write_openpcdet_meta(const std::string& path, const std::vector<std::string>& frame_ids,
                          const std::vector<core::FrameTruth>& truth, const std::string& source);

}  // namespace fmcw::io
