#pragma once
// Colours for exported clouds: Doppler on a diverging scale, labels by instance, semantic
// classes by a fixed palette.

#include <cstdint>
#include <vector>

#include "fmcw/io/pcd.hpp"
#include "fmcw/io/point_labels.hpp"

namespace fmcw::io {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

/// Blue for approaching (v = -full_scale and below), white at rest, red for receding
/// (v = +full_scale and above), linear in between. full_scale_mps > 0.
Rgb doppler_color(double v_mps, double full_scale_mps);

/// Grey for the static world (instance 0), black for unlabeled points, and for instance k a
/// hue stepped by the golden angle (neighbouring ids look different), full brightness where
/// the point moves, half where it does not (a parked car).
Rgb label_color(std::uint16_t semantic, std::uint16_t instance);

/// The colour of a class id of the field `class` (core::ClassTable): SemanticKITTI's own colour
/// for its classes (its color_map, as RGB), black for 0 (unlabeled), a colour of its own for
/// van, grey (128, 128, 128) for any other id (a scenario's own classes). Distinct classes of the
/// built-in table get distinct colours (docs/FORMATS.md lists them).
Rgb class_color(std::uint16_t class_id);
/// Grey, the colour class_color gives ids it does not know.
constexpr Rgb kUnknownClassColor{128, 128, 128};

/// One colour per point of the cloud from its field `v`; std::invalid_argument naming where
/// when the cloud has no `v`.
std::vector<Rgb> doppler_colors(const PcdCloud& cloud, double full_scale_mps, const std::string& where);
std::vector<Rgb> label_colors(const PointLabels& labels);
/// One colour per point from its field `class`; std::invalid_argument naming where when the
/// cloud has no `class` (frames without ground truth, or datasets written before classes were)
/// or a point with a return has a class that is not an integer in 0..65535.
std::vector<Rgb> class_colors(const PcdCloud& cloud, const std::string& where);

}  // namespace fmcw::io
