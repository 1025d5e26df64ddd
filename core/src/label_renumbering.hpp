#pragma once
// Internal to core: labels renumbered by first pixel (row-major), as the pipeline numbers
// clusters.

#include <cstdint>
#include <vector>

namespace fmcw::core {

/// Gives each key (>= 0, below num_keys) a new label 1, 2, ... in the order of its first pixel
/// among the listed ones (ascending) and writes it to labels; listed pixels whose key_of(i) is
/// negative, and all pixels not listed, keep their label. key_of(i) is called once per listed
/// pixel, in order, before labels[i] is written. Returns per new label its key (element 0
/// unused, -1).
template <class KeyOf>
std::vector<std::int32_t> renumber_listed_by_first_pixel(std::vector<std::int32_t>& labels,
                                                         const std::vector<std::uint32_t>& listed,
                                                         std::size_t num_keys, const KeyOf& key_of) {
  std::vector<std::int32_t> new_label(num_keys, 0);
  std::vector<std::int32_t> key_of_new(1, -1);
  for (const std::uint32_t i : listed) {
    const std::int32_t key = key_of(i);
    if (key < 0) continue;
    std::int32_t& nl = new_label[static_cast<std::size_t>(key)];
    if (nl == 0) {
      nl = static_cast<std::int32_t>(key_of_new.size());
      key_of_new.push_back(key);
    }
    labels[i] = nl;
  }
  return key_of_new;
}

}  // namespace fmcw::core
