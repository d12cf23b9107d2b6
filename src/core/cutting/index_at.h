#pragma once

#include <cstddef>
#include <vector>

namespace surgical_sim::core::cutting_index {

/// Element i of a vector indexed by an int id (node, element, copy, edge, face slot): the one
/// place where the cutter's signed ids convert to std::size_t. Precondition 0 <= i < v.size().
template <class T>
decltype(auto) at(std::vector<T>& v, int i) {
  return v[static_cast<std::size_t>(i)];
}

template <class T>
decltype(auto) at(const std::vector<T>& v, int i) {
  return v[static_cast<std::size_t>(i)];
}

/// A count n >= 0 of ids as a container size.
inline std::size_t toSize(int n) { return static_cast<std::size_t>(n); }

/// Number of elements of v as an int id bound.
template <class T>
int intSize(const std::vector<T>& v) {
  return static_cast<int>(v.size());
}

}  // namespace surgical_sim::core::cutting_index
