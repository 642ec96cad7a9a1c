// An enum's names as one table indexed by its value (the enum's members numbered 0, 1, ... in
// declaration order): to_string and the lookup by name both read it, instead of a switch for one
// and a loop over the members for the other.
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

namespace simreel {

template <class E, std::size_t N>
struct EnumNames {
  std::array<const char*, N> names;

  const char* operator()(E e) const {
    const auto i = (std::size_t)e;
    return i < N ? names[i] : "?";
  }
  /// Every member named (a missing initializer leaves a null: static_assert it at the table).
  constexpr bool complete() const {
    for (const char* n : names)
      if (!n) return false;
    return true;
  }
  std::optional<E> parse(std::string_view name) const {
    for (std::size_t i = 0; i < N; ++i)
      if (name == names[i]) return (E)i;
    return std::nullopt;
  }
};

}  // namespace simreel
