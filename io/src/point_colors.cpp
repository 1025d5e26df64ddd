#include "fmcw/io/point_colors.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "fmcw/core/check.hpp"

namespace fmcw::io {

using core::concat;

namespace {
struct ClassColor {
  std::uint16_t id;
  Rgb rgb;
};
// SemanticKITTI's color_map (semantic-kitti.yaml, there as BGR) for its classes, and van.
constexpr ClassColor kClassColors[] = {
    {0, {0, 0, 0}},         {10, {100, 150, 245}}, {11, {100, 230, 245}}, {13, {100, 80, 250}},
    {15, {30, 60, 150}},    {18, {80, 30, 180}},   {20, {0, 0, 255}},     {30, {255, 30, 30}},
    {31, {255, 40, 200}},   {32, {150, 30, 90}},   {40, {255, 0, 255}},   {44, {255, 150, 255}},
    {48, {75, 0, 75}},      {49, {175, 0, 75}},    {50, {255, 200, 0}},   {51, {255, 120, 50}},
    {52, {255, 150, 0}},    {60, {150, 255, 170}}, {70, {0, 175, 0}},     {71, {135, 60, 0}},
    {72, {150, 240, 80}},   {80, {255, 240, 150}}, {81, {255, 0, 0}},     {99, {50, 255, 255}},
    {100, {0, 120, 180}},  // van: a blue of its own, beside other_vehicle's
};

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

Rgb class_color(std::uint16_t class_id) {
  for (const ClassColor& c : kClassColors) {
    if (c.id == class_id) return c.rgb;
  }
  return kUnknownClassColor;
}

std::vector<Rgb> doppler_colors(const PcdCloud& cloud, double full_scale_mps, const std::string& where) {
  const PcdField* v = cloud.find("v");
  if (!v) throw core::FileError(where + ": no field 'v' to colour by Doppler");
  std::vector<Rgb> colors(cloud.points());
  for (std::size_t i = 0; i < colors.size(); ++i) colors[i] = doppler_color(v->values[i], full_scale_mps);
  return colors;
}

std::vector<Rgb> label_colors(const PointLabels& labels) {
  std::vector<Rgb> colors(labels.semantic.size());
  for (std::size_t i = 0; i < colors.size(); ++i) colors[i] = label_color(labels.semantic[i], labels.instance[i]);
  return colors;
}

std::vector<Rgb> class_colors(const PcdCloud& cloud, const std::string& where) {
  const PcdField* semantic = cloud.find("class");
  if (!semantic) {
    throw core::FileError(where + ": no field 'class' to colour by semantic class (only frames of datasets "
                                  "written by fmcw simulate have it, and not those written before classes were)");
  }
  const PcdField* x = cloud.find("x");
  std::vector<Rgb> colors(cloud.points());
  for (std::size_t i = 0; i < colors.size(); ++i) {
    const double id = semantic->values[i];
    if (!(id >= 0.0 && id <= 65535.0 && id == std::floor(id))) {
      if (x && !std::isfinite(x->values[i])) continue;  // no return: not exported
      throw core::FileError(
    concat(where, ": point ", i, ": class ", id, " is not a class id (an integer in 0..65535)"));
    }
    colors[i] = class_color(static_cast<std::uint16_t>(id));
  }
  return colors;
}

}  // namespace fmcw::io
