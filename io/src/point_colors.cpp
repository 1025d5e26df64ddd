#include "fmcw/io/point_colors.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fmcw/core/check.hpp"

namespace fmcw::io {

namespace {
std::uint8_t channel(double unit) { return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(unit, 0.0, 1.0))); }

// Hue in [0, 1) at full saturation, scaled by value.
Rgb from_hue(double hue, double value) {
  const double h = 6.0 * hue;
  const double f = h - std::floor(h);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h) % 6) {
    case 0: r = 1; g = f; break;
    case 1: r = 1 - f; g = 1; break;
    case 2: g = 1; b = f; break;
    case 3: g = 1 - f; b = 1; break;
    case 4: r = f; b = 1; break;
    default: r = 1; b = 1 - f; break;
  }
  return {channel(r * value), channel(g * value), channel(b * value)};
}
}  // namespace

Rgb doppler_color(double v_mps, double full_scale_mps) {
  FMCW_CHECK_ARG(full_scale_mps > 0.0, "Doppler colour scale must be > 0 m/s, got ", full_scale_mps);
  if (!std::isfinite(v_mps)) return {0, 0, 0};
  const double s = std::clamp(v_mps / full_scale_mps, -1.0, 1.0);
  // White fades to red for receding, to blue for approaching.
  if (s >= 0.0) return {255, channel(1.0 - s), channel(1.0 - s)};
  return {channel(1.0 + s), channel(1.0 + s), 255};
}

Rgb label_color(std::uint16_t semantic, std::uint16_t instance) {
  if (semantic == kSemanticUnlabeled) return {0, 0, 0};
  if (instance == 0) return {150, 150, 150};
  constexpr double kGoldenFraction = 0.6180339887498949;
  const double hue = std::fmod(instance * kGoldenFraction, 1.0);
  const bool moving = semantic >= kSemanticMoving;
  return from_hue(hue, moving ? 1.0 : 0.5);
}

std::vector<Rgb> doppler_colors(const PcdCloud& cloud, double full_scale_mps, const std::string& where) {
  const PcdField* v = cloud.find("v");
  if (!v) throw std::invalid_argument(where + ": no field 'v' to colour by Doppler");
  std::vector<Rgb> colors(cloud.points());
  for (std::size_t i = 0; i < colors.size(); ++i) colors[i] = doppler_color(v->values[i], full_scale_mps);
  return colors;
}

std::vector<Rgb> label_colors(const PointLabels& labels) {
  std::vector<Rgb> colors(labels.semantic.size());
  for (std::size_t i = 0; i < colors.size(); ++i) colors[i] = label_color(labels.semantic[i], labels.instance[i]);
  return colors;
}

}  // namespace fmcw::io
