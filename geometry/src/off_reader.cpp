// ASCII OFF into a polygon soup (off_ply_reader.hpp). The layout CGAL's
// reader accepts for the files sage's users have:
//
//   [ST][C][N]OFF [V F [E]]     the keyword, the counts here or on the next line
//   x y z [...]                 V vertex lines, numbers after z ignored
//   n i1 ... in [...]           F face lines, numbers after the indices ignored
//
// '#' starts a comment to the end of the line; blank lines are skipped.
// What is after the last face is ignored, as CGAL does.
#include "off_ply_reader.hpp"

#include <algorithm>
#include <cmath>

namespace sage::geometry::mesh {

namespace {

using reader::fail;
using reader::shown;

// The file's lines, comments cut and blank lines skipped.
class Lines {
 public:
  explicit Lines(std::string_view data) : data_(data) {}

  /// The tokens of the next line that has any; false at the end.
  bool next(std::vector<std::string_view>& tokens) {
    tokens.clear();
    while (tokens.empty() && pos_ < data_.size()) {
      const std::size_t end = std::min(data_.find('\n', pos_), data_.size());
      std::string_view line = data_.substr(pos_, end - pos_);
      line = line.substr(0, line.find('#'));
      reader::split(line, tokens);
      pos_ = end + 1;
      ++number_;
    }
    return !tokens.empty();
  }

  /// "line N: " for the line last returned.
  std::string at() const { return "line " + std::to_string(number_) + ": "; }
  std::size_t bytes_left() const { return pos_ < data_.size() ? data_.size() - pos_ : 0; }

 private:
  std::string_view data_;
  std::size_t pos_ = 0, number_ = 0;
};

// The first word: [ST][C][N]OFF; the variants this reader does not read
// are refused by name.
void check_keyword(const std::string& path, const Lines& lines, std::string_view word) {
  std::string_view rest = word;
  for (std::string_view prefix : {"ST", "C", "N"})
    if (rest.substr(0, prefix.size()) == prefix && rest.size() > prefix.size()) rest.remove_prefix(prefix.size());
  if (rest == "OFF") return;
  if (rest == "4OFF" || rest == "4nOFF" || rest == "nOFF")
    fail(path, lines.at() + shown(word) + ": homogeneous (4OFF) and n-dimensional (nOFF) OFF files are not supported");
  if (rest.size() >= 4 && rest.substr(rest.size() - 4) == "SKEL")
    fail(path, lines.at() + shown(word) + ": a SKEL file holds points and polylines, not a surface mesh");
  fail(path, lines.at() + "not an OFF file: it begins with " + shown(word) + ", not OFF (or COFF, NOFF, STOFF...)");
}

struct Counts {
  std::size_t vertices = 0, faces = 0;
};

// The keyword and the counts "V F [E]" (E, the edges, is not used).
Counts read_header(const std::string& path, Lines& lines) {
  std::vector<std::string_view> tokens;
  if (!lines.next(tokens)) fail(path, "the file is empty: no OFF header");
  check_keyword(path, lines, tokens[0]);
  tokens.erase(tokens.begin());
  if (tokens.empty() && !lines.next(tokens)) fail(path, "the file ends after its OFF keyword: the counts are missing");
  if (tokens[0] == "BINARY")
    fail(path, lines.at() +
                   "binary OFF is not supported: convert the file to ASCII OFF or to PLY (with MeshLab, for example)");
  if (tokens.size() < 2 || tokens.size() > 3)
    fail(path, lines.at() + "expected the counts 'vertices faces edges', found " + std::to_string(tokens.size()) +
                   " word(s)");
  Counts counts;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const auto n = reader::parse<std::int64_t>(tokens[i]);
    if (!n || *n < 0)
      fail(path, lines.at() + "the " +
                     (i == 0   ? "vertex"
                      : i == 1 ? "face"
                               : "edge") +
                     " count " + shown(tokens[i]) + " is not a non-negative integer");
    if (i == 0) counts.vertices = static_cast<std::size_t>(*n);
    if (i == 1) counts.faces = static_cast<std::size_t>(*n);
  }
  // What the rest of the file can hold: a vertex line takes at least 6
  // bytes ("0 0 0\n"), a face line 2 ("0\n", a degenerate face --repair
  // drops); the last line may lack its newline.
  const std::size_t room = lines.bytes_left() + 1;
  if (counts.vertices > room / 6)
    fail(path, lines.at() + "the header's " + std::to_string(counts.vertices) + " vertices cannot fit in the " +
                   std::to_string(lines.bytes_left()) + " bytes that follow it (a vertex line takes at least 6)");
  if (counts.faces > (room - 6 * counts.vertices) / 2)
    fail(path, lines.at() + "the header's " + std::to_string(counts.faces) + " faces (after " +
                   std::to_string(counts.vertices) + " vertices) cannot fit in the " +
                   std::to_string(lines.bytes_left()) +
                   " bytes that follow it (a vertex line takes at least 6 bytes, a face line 2)");
  return counts;
}

// Every word of a vertex or face line is a number (colours, normals and
// texture coordinates included).
void check_numbers(const std::string& path, const Lines& lines, const std::vector<std::string_view>& tokens,
                   std::size_t from, const std::string& what) {
  for (std::size_t i = from; i < tokens.size(); ++i)
    if (!reader::parse<double>(tokens[i])) fail(path, lines.at() + what + ": " + shown(tokens[i]) + " is not a number");
}

Point read_vertex(const std::string& path, Lines& lines, std::size_t v, const Counts& counts,
                  std::vector<std::string_view>& tokens) {
  const std::string what = "vertex " + std::to_string(v);
  if (!lines.next(tokens))
    fail(path, "the file ends after " + std::to_string(v) + " of its " + std::to_string(counts.vertices) + " vertices");
  if (tokens.size() < 3)
    fail(path, lines.at() + what + " has " + std::to_string(tokens.size()) + " number(s), expected x y z");
  check_numbers(path, lines, tokens, 0, what);
  double xyz[3];
  for (int k = 0; k < 3; ++k) {
    xyz[k] = *reader::parse<double>(tokens[k]);
    if (!std::isfinite(xyz[k]))
      fail(path, lines.at() + what + ": the coordinate " + shown(tokens[k]) + " is not a finite number");
  }
  return Point(xyz[0], xyz[1], xyz[2]);
}

std::vector<std::size_t> read_face(const std::string& path, Lines& lines, std::size_t f, const Counts& counts,
                                   std::vector<std::string_view>& tokens) {
  const std::string what = "face " + std::to_string(f);
  if (!lines.next(tokens))
    fail(path, "the file ends after " + std::to_string(f) + " of its " + std::to_string(counts.faces) + " faces");
  const auto n = reader::parse<std::int64_t>(tokens[0]);
  if (!n) fail(path, lines.at() + what + ": its vertex count " + shown(tokens[0]) + " is not an integer");
  // Faces of 0 to 2 vertices pass: --repair drops them, else read_mesh_soup refuses them.
  if (*n < 0) fail(path, lines.at() + what + " has " + std::to_string(*n) + " vertices (at least 3 are needed)");
  // The line holds the indices: its length bounds the allocation.
  if (static_cast<std::uint64_t>(*n) > tokens.size() - 1)
    fail(path, lines.at() + what + " has " + std::to_string(*n) + " vertices, but its line holds only " +
                   std::to_string(tokens.size() - 1) + " number(s) after the count");
  const auto size = static_cast<std::size_t>(*n);
  std::vector<std::size_t> polygon(size);
  for (std::size_t j = 0; j < size; ++j) {
    const auto index = reader::parse<std::int64_t>(tokens[j + 1]);
    if (!index) fail(path, lines.at() + what + ": the vertex index " + shown(tokens[j + 1]) + " is not an integer");
    if (*index < 0 || static_cast<std::uint64_t>(*index) >= counts.vertices)
      fail(path, lines.at() + what + " refers to vertex " + std::to_string(*index) + ", but there are only " +
                     std::to_string(counts.vertices) + " vertices (0 to " +
                     (counts.vertices ? std::to_string(counts.vertices - 1) : std::string("none")) + ")");
    polygon[j] = static_cast<std::size_t>(*index);
  }
  check_numbers(path, lines, tokens, size + 1, what + " (colour)");
  return polygon;
}

}  // namespace

PolygonSoup read_off(const std::string& path, std::string_view data) {
  Lines lines(data);
  const Counts counts = read_header(path, lines);
  PolygonSoup soup;
  soup.points.reserve(counts.vertices);  // bounded by the file's size (read_header)
  soup.polygons.reserve(std::min<std::size_t>(counts.faces, lines.bytes_left() / 8));  // a triangle's line: 8 bytes
  std::vector<std::string_view> tokens;
  for (std::size_t v = 0; v < counts.vertices; ++v) soup.points.push_back(read_vertex(path, lines, v, counts, tokens));
  for (std::size_t f = 0; f < counts.faces; ++f) soup.polygons.push_back(read_face(path, lines, f, counts, tokens));
  return soup;
}

}  // namespace sage::geometry::mesh
