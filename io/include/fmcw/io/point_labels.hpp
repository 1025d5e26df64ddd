#pragma once
// Per-point semantic and instance labels in SemanticKITTI's class numbering, from either the
// motion estimate of `fmcw process` (field `label`) or a dataset's ground truth (fields
// `instance` and `moving`, and `class` where the frame has it). Used by the exports.
//
// Mapping (docs/FORMATS.md, "Exports"):
// - truth with `class` (core::ClassTable ids): ids below 100 are SemanticKITTI's own, van 100
//   is its other-vehicle 20, any other id of 100 and above (a scenario's own class) its
//   other-object 99; on pixels whose surface moves, the class's moving code (the table's
//   SemanticClass::moving_id: 252 moving-car ... 259 moving-other-vehicle), or the moving-object
//   benchmark's generic 251 "moving" for a class SemanticKITTI has no moving code for; class 0
//   (no class) stays 0.
// - truth without `class` (datasets written before it): static world 9 "static" and generic
//   moving 251 "moving" as in SemanticKITTI's moving-object benchmark; actors of a known class
//   name get that class's code, its "moving-" code on pixels whose surface moves:
//     car, van 10/252 · truck 18/258 · bus 13/257 · cyclist, bicyclist 31/253 ·
//     motorcyclist 32/255 · pedestrian, person 30/254 · any other actor 99/251.
// - estimate: moving cluster 251 · static 9 · unassigned (region too small) 0.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "fmcw/io/pcd.hpp"

namespace fmcw::io {

enum class LabelSource {
  kAuto,      ///< the estimate when the cloud has `label`, else the ground truth
  kEstimate,  ///< field `label`: -1 no return, -2 unassigned, 0 static, k moving cluster k
  kTruth,     ///< fields `instance` (actor id, 0 static world) and `moving`
};

/// "auto", "estimate" or "truth"; std::invalid_argument otherwise.
LabelSource parse_label_source(const std::string& text);

/// One entry per point of the cloud (points without a return included: their labels are 0).
struct PointLabels {
  std::vector<std::uint16_t> semantic;  ///< SemanticKITTI class code
  std::vector<std::uint16_t> instance;  ///< cluster or actor id, 0 for the static world
  LabelSource source = LabelSource::kAuto;  ///< the source used (never kAuto)
};

constexpr std::uint16_t kSemanticUnlabeled = 0;
constexpr std::uint16_t kSemanticStatic = 9;
constexpr std::uint16_t kSemanticMoving = 251;

/// Class code of an actor class name (as in a scenario's `class:`), static or moving: the
/// mapping of frames without the field `class`.
std::uint16_t semantic_class(const std::string& actor_class, bool moving);

/// SemanticKITTI's code of a class id of the field `class` (core::ClassTable), static or moving.
std::uint16_t semantic_kitti_class(std::uint16_t class_id, bool moving);

/// Labels of every point. Ground truth takes each point's class from the field `class` when the
/// cloud has it; otherwise from actor_classes, which maps actor ids to class names (from
/// objects.csv; ids it lacks are "any other actor"). std::invalid_argument naming where for a
/// missing field, a label below -2, an id above 65535 (SemanticKITTI keeps instances in 16
/// bits), or a class that is not an integer in 0..65535.
PointLabels point_labels(const PcdCloud& cloud, LabelSource source, const std::map<std::uint32_t, std::string>& actor_classes,
                         const std::string& where);

}  // namespace fmcw::io
