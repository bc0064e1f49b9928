#pragma once
// sage's own readers of OFF (off_reader.cpp) and PLY (ply_reader.cpp)
// meshes into a polygon soup, in place of CGAL 5.5's, which trust the file:
// they allocate counts and list sizes as read (gigabytes from a file of 40
// bytes), loop on a count of -1, cast negative sizes to std::size_t and
// write through a wild pointer on a "property" line before any "element"
// (fuzz/regressions/mesh/). On valid files they give the points and
// polygons CGAL::IO::read_polygon_soup gives (tests/geometry/
// mesh_reader_test.cpp); on bad ones a ModelError naming the file, the
// place (line, element, item, face) and what is wrong. Every count and list
// size is checked against the bytes left in the file before anything is
// allocated for it.

#include "mesh_internal.hpp"

#include <locale.h>
#include <stdlib.h>
#include <charconv>
#include <clocale>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <type_traits>
#include <vector>

namespace sage::geometry::mesh {

struct PolygonSoup {
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;  // vertex indices into points
};

/// ASCII OFF (also COFF, NOFF, CNOFF, STOFF...: numbers after x y z and
/// after a face's indices are ignored). Binary, homogeneous (4OFF),
/// n-dimensional (nOFF) and SKEL files are refused. `data` is the whole
/// file, `path` names it in errors.
PolygonSoup read_off(const std::string& path, std::string_view data);

/// PLY, ASCII or binary (little or big endian): points from the x, y, z of
/// the "vertex" elements (any numeric type), polygons from the integer list
/// "vertex_indices" (or "vertex_index") of the "face" elements; other
/// properties and elements are skipped.
PolygonSoup read_ply(const std::string& path, std::string_view data);

// ---- shared by the two readers ----------------------------------------------
namespace reader {

[[noreturn]] inline void fail(const std::string& path, const std::string& what) {
  throw ModelError(path + ": " + what);
}

/// A token as it goes in a message: quoted, at most 24 characters, bytes
/// that are not printable ASCII as \xNN.
inline std::string shown(std::string_view token) {
  static const char* const kHex = "0123456789abcdef";
  std::string s = "'";
  for (std::size_t i = 0; i < token.size() && i < 24; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 32 && c < 127) {
      s += static_cast<char>(c);
    } else {
      s += "\\x";
      s += kHex[c >> 4];
      s += kHex[c & 15];
    }
  }
  return s + (token.size() > 24 ? "...'" : "'");
}

/// The whole token as a number of type T (std::from_chars: no locale,
/// correctly rounded like the sscanf of CGAL's readers); a leading '+' is
/// allowed. Floating point: "inf" and "nan" parse, and so does a number
/// beyond the type's range, to +-inf or (under) a denormal or zero, as
/// sscanf has it; finiteness is the caller's check. Integers out of T's
/// range do not parse.
template <typename T>
std::optional<T> parse(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-') token.remove_prefix(1);
  T value{};
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ptr != end) return std::nullopt;
  if constexpr (std::is_floating_point_v<T>) {
    if (ec == std::errc::result_out_of_range) {  // from_chars leaves value as it was
      // strtod in the C locale (a host program's locale may use a decimal comma).
      static const locale_t c_locale = newlocale(LC_ALL_MASK, "C", static_cast<locale_t>(nullptr));
      const std::string copy(token);
      return static_cast<T>(std::is_same_v<T, float> ? strtof_l(copy.c_str(), nullptr, c_locale)
                                                     : strtod_l(copy.c_str(), nullptr, c_locale));
    }
  }
  if (ec != std::errc()) return std::nullopt;
  return value;
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

/// Splits `line` into its whitespace-separated tokens.
inline void split(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

}  // namespace reader

}  // namespace sage::geometry::mesh
