#include "fmcw/core/semantic_classes.hpp"

#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::core {

ClassTable ClassTable::builtin() {
  // SemanticKITTI's label ids (semantic-kitti.yaml), and its moving variants.
  ClassTable t;
  t.classes_ = {
      {0, "unlabeled", 0},         {10, "car", 252},           {11, "bicycle", 0},        {13, "bus", 257},
      {15, "motorcycle", 0},       {18, "truck", 258},         {20, "other_vehicle", 259}, {30, "pedestrian", 254},
      {31, "cyclist", 253},        {32, "motorcyclist", 255},  {40, "road", 0},            {44, "parking", 0},
      {48, "sidewalk", 0},         {49, "ground", 0},          {50, "building", 0},        {51, "fence", 0},
      {52, "other_structure", 0},  {60, "lane_marking", 0},    {70, "vegetation", 0},      {71, "trunk", 0},
      {72, "terrain", 0},          {80, "pole", 0},            {81, "traffic_sign", 0},    {99, "other_object", 0},
      {100, "van", 259},
  };
  return t;
}

void ClassTable::add(const std::string& name, std::uint64_t id) {
  // Class names are cells of CSV tables (objects.csv, the evaluation's tables) and lines of
  // YAML: printable, no comma or quote, short.
  if (name.empty()) throw InputError("class name is empty");
  if (name.size() > kMaxClassNameLength) {
    throw InputError("class name '" + name.substr(0, 32) + "...' is longer than " +
                     std::to_string(kMaxClassNameLength) + " characters");
  }
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f || c == ',' || c == '"') {
      std::string shown;
      for (const char d : name) {
        const auto v = static_cast<unsigned char>(d);
        shown += v < 0x20 || v == 0x7f ? "\\x" + std::string(1, "0123456789abcdef"[v >> 4]) + "0123456789abcdef"[v & 15]
                                       : std::string(1, d);
      }
      throw InputError("class name '" + shown + "' holds " +
                       (c == ',' ? "a comma" : c == '"' ? "a double quote" : "a control character") +
                       ": class names are written into CSV tables; use letters, digits, spaces and _ - . /");
    }
  }
  if (id == 0 || id > 65535) {
    throw InputError("class '" + name + "': id " + std::to_string(id) + " is not in [1, 65535]");
  }
  for (const SemanticClass& c : classes_) {
    if (c.name == name) throw InputError("class '" + name + "' is defined already (id " + std::to_string(c.id) + ")");
    if (c.id == id) {
      throw InputError("class '" + name + "': id " + std::to_string(id) + " is taken by class '" + c.name + "'");
    }
  }
  classes_.push_back({static_cast<std::uint16_t>(id), name, 0});
}

std::optional<std::uint16_t> ClassTable::find(const std::string& name) const {
  for (const SemanticClass& c : classes_) {
    if (c.name == name) return c.id;
  }
  return std::nullopt;
}

const SemanticClass* ClassTable::get(std::uint16_t id) const {
  for (const SemanticClass& c : classes_) {
    if (c.id == id) return &c;
  }
  return nullptr;
}

std::string ClassTable::names() const {
  std::string out;
  for (const SemanticClass& c : classes_) {
    if (c.id == kUnlabeledClass) continue;
    out += (out.empty() ? "" : ", ") + c.name;
  }
  return out;
}

}  // namespace fmcw::core
