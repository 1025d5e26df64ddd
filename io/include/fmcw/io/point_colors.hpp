#pragma once
// Colours for exported clouds: Doppler on a diverging scale, labels by instance.

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

/// One colour per point of the cloud from its field `v`; std::invalid_argument naming where
/// when the cloud has no `v`.
std::vector<Rgb> doppler_colors(const PcdCloud& cloud, double full_scale_mps, const std::string& where);
std::vector<Rgb> label_colors(const PointLabels& labels);

}  // namespace fmcw::io
