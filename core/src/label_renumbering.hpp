#pragma once
// Internal to core: labels renumbered by first pixel (row-major), as the pipeline numbers
// clusters.

#include <cstdint>
#include <vector>

namespace fmcw::core {

namespace detail {
// Renumbers the pixels for_each_pixel(f) hands to f, in ascending order.
template <class ForEachPixel, class KeyOf>
std::vector<std::int32_t> renumber_in_order(std::vector<std::int32_t>& labels, std::size_t num_keys,
                                            const ForEachPixel& for_each_pixel, const KeyOf& key_of) {
  std::vector<std::int32_t> new_label(num_keys, 0);
  std::vector<std::int32_t> key_of_new(1, -1);
  for_each_pixel([&](std::size_t i) {
    const std::int32_t key = key_of(i);
    if (key < 0) return;
    std::int32_t& nl = new_label[static_cast<std::size_t>(key)];
    if (nl == 0) {
      nl = static_cast<std::int32_t>(key_of_new.size());
      key_of_new.push_back(key);
    }
    labels[i] = nl;
  });
  return key_of_new;
}
}  // namespace detail

/// Gives each key (>= 0, below num_keys) a new label 1, 2, ... in the order of its first pixel
/// and writes it to labels; pixels whose key_of(i) is negative keep their label. key_of(i) is
/// called once per pixel, in order, before labels[i] is written. Returns per new label its key
/// (element 0 unused, -1).
template <class KeyOf>
std::vector<std::int32_t> renumber_by_first_pixel(std::vector<std::int32_t>& labels, std::size_t num_keys, const KeyOf& key_of) {
  return detail::renumber_in_order(
      labels, num_keys,
      [&](const auto& f) {
        for (std::size_t i = 0; i < labels.size(); ++i) f(i);
      },
      key_of);
}

/// renumber_by_first_pixel over the listed pixels only (ascending): the others keep their
/// label, as if their key were negative.
template <class KeyOf>
std::vector<std::int32_t> renumber_listed_by_first_pixel(std::vector<std::int32_t>& labels, const std::vector<std::uint32_t>& listed,
                                                         std::size_t num_keys, const KeyOf& key_of) {
  return detail::renumber_in_order(
      labels, num_keys,
      [&](const auto& f) {
        for (const std::uint32_t i : listed) f(i);
      },
      key_of);
}

}  // namespace fmcw::core
