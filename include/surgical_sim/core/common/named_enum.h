#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace surgical_sim::core {

/// One entry of an enum's name table: the value and its name in scene files and CSV rows.
template <class Enum>
struct EnumName {
  Enum value;
  const char* name;
};

/// Name of `value` in `table` (every value of the enum has an entry).
template <class Enum, std::size_t N>
const char* enumName(const std::array<EnumName<Enum>, N>& table, Enum value) {
  for (const auto& e : table)
    if (e.value == value) return e.name;
  return "?";
}

/// The value named `name` in `table`, or nullopt.
template <class Enum, std::size_t N>
std::optional<Enum> enumFromName(const std::array<EnumName<Enum>, N>& table,
                                 const std::string& name) {
  for (const auto& e : table)
    if (name == e.name) return e.value;
  return std::nullopt;
}

/// "a, b, c": the names of `table`, for error messages.
template <class Enum, std::size_t N>
std::string enumNames(const std::array<EnumName<Enum>, N>& table) {
  std::string out;
  for (const auto& e : table) out += (out.empty() ? "" : ", ") + std::string(e.name);
  return out;
}

}  // namespace surgical_sim::core
