// SPDX-License-Identifier: Apache-2.0
#pragma once

#include <ostream>
#include <type_traits>

namespace dvi {

/// Writes any public enum of dvi by its name, ToString(value): a status,
/// a method or a scheme reads in a log or a test's failure message as the
/// word the scene files and summary.json use ("not-index-one", "7.2").
/// Found by argument-dependent lookup for every enum of namespace dvi that
/// has a ToString.
template <typename Enum, typename = std::enable_if_t<std::is_enum_v<Enum>>>
auto operator<<(std::ostream& out, Enum value) -> decltype(out << ToString(value)) {
  return out << ToString(value);
}

}  // namespace dvi
