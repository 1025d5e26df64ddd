#include "fmcw/io/point_labels.hpp"

#include <cmath>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/core/semantic_classes.hpp"

namespace fmcw::io {

using core::concat;

namespace {
struct ClassCodes {
  const char* name;
  std::uint16_t still;
  std::uint16_t moving;
};
// SemanticKITTI codes of the classes our scenarios use, and their usual synonyms.
constexpr ClassCodes kClasses[] = {
    {"car", 10, 252},         {"van", 10, 252},        {"truck", 18, 258},         {"bus", 13, 257},
    {"cyclist", 31, 253},     {"bicyclist", 31, 253},  {"motorcyclist", 32, 255},  {"pedestrian", 30, 254},
    {"person", 30, 254},
};
constexpr std::uint16_t kOtherObject = 99;
constexpr double kMaxInstance = 65535.0;

// Classes of ours (ids of 100 and above in core::ClassTable) that SemanticKITTI has under
// another name: their still code there (the moving one is the table's moving_id).
struct OurClass {
  std::uint16_t id;
  std::uint16_t semantic_kitti;
};
constexpr OurClass kOurClasses[] = {{100, 20}};  // van: other-vehicle
constexpr std::uint16_t kFirstClassOfOurs = 100;

const PcdField& require(const PcdCloud& cloud, const char* name, const std::string& where, const char* why) {
  const PcdField* f = cloud.find(name);
  if (!f) throw core::FileError(concat(where, ": no field '", name, "' for ", why));
  return *f;
}

std::uint16_t instance_id(double value, std::size_t point, const std::string& where) {
  if (!(value >= 0.0 && value <= kMaxInstance)) {
    throw core::FileError(concat(where, ": point ", point, ": id ", value,
                                 " does not fit SemanticKITTI's 16-bit instance field (0..65535)"));
  }
  return static_cast<std::uint16_t>(value);
}

std::uint16_t class_of_point(double value, std::size_t point, const std::string& where) {
  if (!(value >= 0.0 && value <= 65535.0 && value == std::floor(value))) {
    throw core::FileError(
  concat(where, ": point ", point, ": class ", value, " is not a class id (an integer in 0..65535)"));
  }
  return static_cast<std::uint16_t>(value);
}
}  // namespace

LabelSource parse_label_source(const std::string& text) {
  if (text == "auto") return LabelSource::kAuto;
  if (text == "estimate") return LabelSource::kEstimate;
  if (text == "truth") return LabelSource::kTruth;
  throw core::InputError("label source must be auto, estimate or truth, got '" + text + "'");
}

std::uint16_t semantic_class(const std::string& actor_class, bool moving) {
  for (const ClassCodes& c : kClasses) {
    if (actor_class == c.name) return moving ? c.moving : c.still;
  }
  return moving ? kSemanticMoving : kOtherObject;
}

std::uint16_t semantic_kitti_class(std::uint16_t class_id, bool moving) {
  static const core::ClassTable kTable = core::ClassTable::builtin();
  if (class_id == core::kUnlabeledClass) return kSemanticUnlabeled;
  if (moving) {
    const core::SemanticClass* c = kTable.get(class_id);
    return c && c->moving_id != 0 ? c->moving_id : kSemanticMoving;
  }
  if (class_id < kFirstClassOfOurs) return class_id;
  for (const OurClass& c : kOurClasses) {
    if (c.id == class_id) return c.semantic_kitti;
  }
  return kOtherObject;
}

PointLabels point_labels(const PcdCloud& cloud, LabelSource source, const std::map<std::uint32_t, std::string>& actor_classes,
                         const std::string& where) {
  if (source == LabelSource::kAuto) {
    if (cloud.find("label")) {
      source = LabelSource::kEstimate;
    } else if (cloud.find("instance")) {
      source = LabelSource::kTruth;
    } else {
      throw core::FileError(concat(where, ": no labels: the cloud has neither 'label' (fmcw process output) "
                                          "nor 'instance' and 'moving' (ground truth)"));
    }
  }
  const std::size_t n = cloud.points();
  PointLabels out;
  out.source = source;
  out.semantic.assign(n, kSemanticUnlabeled);
  out.instance.assign(n, 0);
  const PcdField& x = require(cloud, "x", where, "positions");
  if (source == LabelSource::kEstimate) {
    const PcdField& label = require(cloud, "label", where, "estimated labels");
    for (std::size_t i = 0; i < n; ++i) {
      const double l = label.values[i];
      if (!(l >= -2.0)) throw core::FileError(concat(where, ": point ", i, ": label ", l, " is below -2"));
      if (l == 0.0) {
        out.semantic[i] = kSemanticStatic;
      } else if (l > 0.0) {
        out.semantic[i] = kSemanticMoving;
        out.instance[i] = instance_id(l, i, where);
      }
    }
    return out;
  }
  const PcdField& instance = require(cloud, "instance", where, "ground-truth labels");
  const PcdField& moving = require(cloud, "moving", where, "ground-truth labels");
  const PcdField* semantic = cloud.find("class");  // absent in datasets written before it
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(x.values[i])) continue;  // no return
    const bool is_moving = moving.values[i] != 0.0;
    const std::uint16_t id = instance_id(instance.values[i], i, where);
    out.instance[i] = id;
    if (semantic) {
      out.semantic[i] = semantic_kitti_class(class_of_point(semantic->values[i], i, where), is_moving);
    } else if (id == 0) {
      out.semantic[i] = is_moving ? kSemanticMoving : kSemanticStatic;
    } else {
      const auto it = actor_classes.find(id);
      out.semantic[i] = semantic_class(it == actor_classes.end() ? std::string() : it->second, is_moving);
    }
  }
  return out;
}

}  // namespace fmcw::io
