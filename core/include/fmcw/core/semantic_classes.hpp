#pragma once
// The semantic classes of the ground truth: every pixel carries one (PCD field `class`), the
// static world included. Ids are SemanticKITTI's where SemanticKITTI has the class, so its
// labels need no mapping; the table a dataset used is written into its dataset.yaml.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace fmcw::core {

struct SemanticClass {
  std::uint16_t id = 0;
  std::string name;
  /// SemanticKITTI's code for the class when it moves (252 moving-car, ...); 0: the class has
  /// no moving variant there (the static world, and classes SemanticKITTI does not have).
  std::uint16_t moving_id = 0;
};

/// Class 0: no return, or a surface with no class.
constexpr std::uint16_t kUnlabeledClass = 0;

/// Longest class name (the name is a cell of CSV tables and a key of dataset.yaml).
constexpr std::size_t kMaxClassNameLength = 64;

class ClassTable {
 public:
  /// The built-in classes (docs/FORMATS.md): the road scene's static classes and its actors,
  /// with SemanticKITTI's ids and names where it has the class (ours: pedestrian for its person,
  /// cyclist for its bicyclist, ground for its other-ground), and `van` (100) beside.
  static ClassTable builtin();

  /// Adds a class of a scenario's own. Throws core::InputError when the name or the id is
  /// taken already (naming the class that has it), the id is 0 or above 65535, or the name is
  /// empty, longer than kMaxClassNameLength or holds a comma, a double quote or a control
  /// character (names are cells of CSV tables).
  void add(const std::string& name, std::uint64_t id);
  /// The id of a class name; nullopt when the table has no such class.
  std::optional<std::uint16_t> find(const std::string& name) const;
  /// The class of an id; nullptr when the table has none.
  const SemanticClass* get(std::uint16_t id) const;
  const std::vector<SemanticClass>& classes() const { return classes_; }
  /// "road, sidewalk, ..." for messages.
  std::string names() const;

 private:
  std::vector<SemanticClass> classes_;
};

}  // namespace fmcw::core
