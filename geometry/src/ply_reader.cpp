// PLY into a polygon soup (off_ply_reader.hpp):
//
//   ply
//   format ascii|binary_little_endian|binary_big_endian 1.0
//   comment ... / obj_info ...
//   element NAME COUNT
//   property TYPE NAME                       TYPE: char uchar short ushort int
//   property list SIZETYPE ITEMTYPE NAME     uint float double, or int8 ... float64
//   end_header
//   the items of each element in turn, each its properties in turn
//   (ASCII: numbers separated by white space; binary: packed)
//
// Points: the x, y, z of each "vertex" element (any numeric type); polygons:
// the integer list "vertex_indices" (or "vertex_index") of each "face"
// element; the rest is skipped by its size. Before anything is allocated,
// each element's count and each list's size is checked against what the
// bytes left can hold (ASCII: 2 bytes a number at least; binary: the
// types' sizes).
#include "off_ply_reader.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace sage::geometry::mesh {

namespace {

using reader::fail;
using reader::shown;

// ---- header -----------------------------------------------------------------

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct TypeInfo {
  std::string_view name, alias;
  Type type;
  std::size_t size;
  double min, max;  // integers: the range
};

constexpr TypeInfo kTypes[] = {
    {"char", "int8", Type::Int8, 1, -128, 127},
    {"uchar", "uint8", Type::UInt8, 1, 0, 255},
    {"short", "int16", Type::Int16, 2, -32768, 32767},
    {"ushort", "uint16", Type::UInt16, 2, 0, 65535},
    {"int", "int32", Type::Int32, 4, -2147483648.0, 2147483647.0},
    {"uint", "uint32", Type::UInt32, 4, 0, 4294967295.0},
    {"float", "float32", Type::Float32, 4, 0, 0},
    {"double", "float64", Type::Float64, 8, 0, 0},
};

const TypeInfo& info(Type t) { return kTypes[static_cast<int>(t)]; }
bool is_integer(Type t) { return t != Type::Float32 && t != Type::Float64; }
/// "an int", "a float".
std::string type_with_article(Type t) { return (t == Type::Int32 ? "an " : "a ") + std::string(info(t).name); }

struct Property {
  std::string name;
  Type type = Type::Float64;      // the value's type (a list's: its items')
  std::optional<Type> list_size;  // a list: the type of its size
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::size_t line = 0;  // of the header
  std::vector<Property> properties;

  /// The index of the property `name`, or nothing.
  std::optional<std::size_t> find(std::string_view property) const {
    for (std::size_t k = 0; k < properties.size(); ++k)
      if (properties[k].name == property) return k;
    return std::nullopt;
  }
  std::string named() const { return "element '" + name + "' (line " + std::to_string(line) + ")"; }
};

enum class Format { Ascii, LittleEndian, BigEndian };

struct Header {
  Format format = Format::Ascii;
  std::vector<Element> elements;
  std::size_t data = 0;  // the offset of the data, after end_header's line
  std::size_t lines = 0;
};

std::optional<Type> type_named(std::string_view name) {
  for (const TypeInfo& t : kTypes)
    if (name == t.name || name == t.alias) return t.type;
  return std::nullopt;
}

Type parse_type(const std::string& path, const std::string& at, std::string_view name) {
  const auto type = type_named(name);
  if (!type)
    fail(path, at + "unknown property type " + shown(name) +
                   " (known: char, uchar, short, ushort, int, uint, float, double, or int8 ... float64)");
  return *type;
}

void parse_format(const std::string& path, const std::string& at, const std::vector<std::string_view>& t, Header& h) {
  if (t.size() < 2) fail(path, at + "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
  if (t[1] == "ascii")
    h.format = Format::Ascii;
  else if (t[1] == "binary_little_endian")
    h.format = Format::LittleEndian;
  else if (t[1] == "binary_big_endian")
    h.format = Format::BigEndian;
  else
    fail(path, at + "unknown format " + shown(t[1]) + " (ascii, binary_little_endian or binary_big_endian)");
}

void parse_element(const std::string& path, const std::string& at, const std::vector<std::string_view>& t,
                   std::size_t line, Header& h) {
  if (t.size() != 3) fail(path, at + "expected 'element NAME COUNT'");
  const auto count = reader::parse<std::uint64_t>(t[2]);
  if (!count)
    fail(path, at + "element " + shown(t[1]) + ": its count " + shown(t[2]) + " is not a non-negative integer");
  h.elements.push_back({std::string(t[1]), *count, line, {}});
}

void parse_property(const std::string& path, const std::string& at, const std::vector<std::string_view>& t, Header& h) {
  if (h.elements.empty())
    fail(path, at + "a 'property' line before any 'element' line: the property belongs to no element");
  Property p;
  if (t.size() >= 2 && t[1] == "list") {
    if (t.size() != 5) fail(path, at + "expected 'property list SIZETYPE ITEMTYPE NAME'");
    p.list_size = parse_type(path, at, t[2]);
    if (!is_integer(*p.list_size)) fail(path, at + "a list's size type must be an integer type, not " + shown(t[2]));
    p.type = parse_type(path, at, t[3]);
    p.name = t[4];
  } else {
    if (t.size() != 3) fail(path, at + "expected 'property TYPE NAME' or 'property list SIZETYPE ITEMTYPE NAME'");
    p.type = parse_type(path, at, t[1]);
    p.name = t[2];
  }
  h.elements.back().properties.push_back(std::move(p));
}

Header read_header(const std::string& path, std::string_view data) {
  if (data.empty()) fail(path, "the file is empty: no PLY header");
  Header h;
  bool format = false;
  std::vector<std::string_view> t;
  std::size_t pos = 0;
  for (std::size_t line = 1;; ++line) {
    if (pos >= data.size())
      fail(path, "the header ends at line " + std::to_string(line - 1) + " without an 'end_header' line");
    const std::size_t end = std::min(data.find('\n', pos), data.size());
    reader::split(data.substr(pos, end - pos), t);
    pos = std::min(end + 1, data.size());
    const std::string at = "line " + std::to_string(line) + ": ";
    if (line == 1) {
      if (t.size() != 1 || t[0] != "ply") fail(path, at + "not a PLY file: it does not begin with a line 'ply'");
      continue;
    }
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format") {
      if (format) fail(path, at + "a second 'format' line");
      parse_format(path, at, t, h);
      format = true;
      continue;
    }
    if (!format) fail(path, at + shown(t[0]) + " before the 'format' line");
    if (t[0] == "end_header") {
      h.data = pos;
      h.lines = line;
      return h;
    }
    if (t[0] == "element")
      parse_element(path, at, t, line, h);
    else if (t[0] == "property")
      parse_property(path, at, t, h);
    else
      fail(path, at + "unknown header keyword " + shown(t[0]));
  }
}

// ---- data -------------------------------------------------------------------

// The values after the header, one at a time, ASCII or binary, and where
// they are for messages: "face 12 (line 40): ..." or "(byte 1234)".
class Data {
 public:
  Data(const std::string& path, std::string_view data, const Header& h)
      : path_(path), data_(data), format_(h.format), pos_(h.data), line_(h.lines + 1), start_(h.data) {}

  /// The item the values read next belong to, for messages.
  void set_item(std::string_view what, std::uint64_t number) {
    what_ = what;
    number_ = number;
  }

  /// Fails naming the item and the place of the value last read.
  [[noreturn]] void fail(const std::string& message) const {
    const std::string place = start_ >= data_.size()     ? "end of file"
                              : format_ == Format::Ascii ? "line " + std::to_string(line_)
                                                         : "byte " + std::to_string(start_);
    reader::fail(path_, std::string(what_) + " " + std::to_string(number_) + " (" + place + "): " + message);
  }

  /// The least bytes a record of `values` numbers takes: in ASCII 2 a
  /// number (a digit and a space), in binary `binary_bytes`.
  std::size_t least(std::size_t binary_bytes, std::size_t values) const {
    return std::max<std::size_t>(format_ == Format::Ascii ? 2 * values : binary_bytes, 1);
  }
  /// How many records of `bytes` bytes the bytes left can hold (ASCII:
  /// the last number may end the file without a space).
  std::uint64_t room(std::size_t bytes) const { return (bytes_left() + (format_ == Format::Ascii ? 1 : 0)) / bytes; }
  std::size_t bytes_left() const { return data_.size() - pos_; }

  /// The next value, of type `type` (exact in a double: at most 32-bit integers).
  double read(Type type) { return format_ == Format::Ascii ? read_ascii(type) : read_binary(type); }

  /// Skips `n` values of type `type`, n <= room(least(its size, 1)).
  void skip(Type type, std::uint64_t n) {
    if (format_ != Format::Ascii) {
      pos_ += static_cast<std::size_t>(n) * info(type).size;
      return;
    }
    for (std::uint64_t i = 0; i < n; ++i) read_ascii(type);
  }

 private:
  std::string_view token(Type type) {
    while (pos_ < data_.size() && reader::is_space(data_[pos_])) line_ += data_[pos_++] == '\n';
    start_ = pos_;
    while (pos_ < data_.size() && !reader::is_space(data_[pos_])) ++pos_;
    if (pos_ == start_) fail("the file ends where " + type_with_article(type) + " was expected");
    return data_.substr(start_, pos_ - start_);
  }

  double read_ascii(Type type) {
    const std::string_view t = token(type);
    const TypeInfo& i = info(type);
    if (type == Type::Float32) {
      if (const auto v = reader::parse<float>(t)) return *v;
    } else if (type == Type::Float64) {
      if (const auto v = reader::parse<double>(t)) return *v;
    } else if (const auto v = reader::parse<std::int64_t>(t)) {
      const auto d = static_cast<double>(*v);
      if (d >= i.min && d <= i.max) return d;
      fail(shown(t) + " is out of the range of " + std::string(i.name) + " (" + std::to_string(std::llround(i.min)) +
           " to " + std::to_string(std::llround(i.max)) + ")");
    }
    fail(shown(t) + " is not " + (is_integer(type) ? "an integer" : "a number") + " (" + std::string(i.name) + ")");
  }

  double read_binary(Type type) {
    const std::size_t size = info(type).size;
    start_ = pos_;
    if (data_.size() - pos_ < size)
      fail("the file ends in the middle of " + type_with_article(type) + " (" + std::to_string(data_.size() - pos_) +
           " of its " + std::to_string(size) + " bytes)");
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, size);
    pos_ += size;
    if ((format_ == Format::LittleEndian) != (std::endian::native == std::endian::little)) std::reverse(b, b + size);
    switch (type) {
      case Type::Int8: return as<std::int8_t>(b);
      case Type::UInt8: return as<std::uint8_t>(b);
      case Type::Int16: return as<std::int16_t>(b);
      case Type::UInt16: return as<std::uint16_t>(b);
      case Type::Int32: return as<std::int32_t>(b);
      case Type::UInt32: return as<std::uint32_t>(b);
      case Type::Float32: return as<float>(b);
      case Type::Float64: return as<double>(b);
    }
    return 0;
  }

  template <typename T>
  static double as(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  }

  const std::string& path_;
  std::string_view data_;
  Format format_;
  std::size_t pos_, line_, start_;  // start_: of the value last read
  std::string what_ = "element";    // a copy: the caller's name may not outlive the item
  std::uint64_t number_ = 0;
};

// ---- elements ---------------------------------------------------------------

// The least bytes an item of `e` takes: a number for each property (a
// list at least its size).
std::size_t item_bytes(const Element& e, const Data& in) {
  std::size_t binary = 0;
  for (const Property& p : e.properties) binary += info(p.list_size ? *p.list_size : p.type).size;
  return in.least(binary, e.properties.size());
}

// What an element is to the soup: which properties are read.
struct Role {
  enum { Other, Vertex, Face } kind = Other;
  std::size_t x = 0, y = 0, z = 0, indices = 0;
};

Role role_of(const std::string& path, const Element& e) {
  Role role;
  if (e.name == "vertex" || e.name == "vertices") {
    role.kind = Role::Vertex;
    std::size_t* slots[] = {&role.x, &role.y, &role.z};
    for (int k = 0; k < 3; ++k) {
      const char name[] = {static_cast<char>('x' + k), 0};
      const auto found = e.find(name);
      if (!found) fail(path, e.named() + " has no property '" + name + "'");
      if (e.properties[*found].list_size)
        fail(path, e.named() + ": its property '" + name + "' is a list, not a number");
      *slots[k] = *found;
    }
  } else if (e.name == "face" || e.name == "faces") {
    role.kind = Role::Face;
    auto found = e.find("vertex_indices");
    if (!found) found = e.find("vertex_index");
    if (!found) fail(path, e.named() + " has no list 'vertex_indices' (nor 'vertex_index')");
    const Property& p = e.properties[*found];
    if (!p.list_size || !is_integer(p.type))
      fail(path, e.named() + ": its property '" + p.name + "' is not a list of integers");
    role.indices = *found;
  }
  return role;
}

// A list's size, checked against the bytes left before anything is read
// or allocated for it.
std::uint64_t read_list_size(Data& in, const Property& p) {
  const double n = in.read(*p.list_size);
  if (n < 0) in.fail("the list '" + p.name + "' has a negative size, " + std::to_string(std::llround(n)));
  const auto size = static_cast<std::uint64_t>(n);
  const std::size_t least = in.least(info(p.type).size, 1);
  if (size > in.room(least))
    in.fail("the list '" + p.name + "' has " + std::to_string(size) + " items, more than the " +
            std::to_string(in.bytes_left()) + " bytes left can hold (an item takes at least " + std::to_string(least) +
            ")");
  return size;
}

std::vector<std::size_t> read_polygon(Data& in, const Property& p, std::uint64_t vertices) {
  // Faces of 0 to 2 vertices pass: --repair drops them, else read_mesh_soup refuses them.
  const std::uint64_t n = read_list_size(in, p);
  std::vector<std::size_t> polygon(static_cast<std::size_t>(n));
  for (std::size_t& v : polygon) {
    const double index = in.read(p.type);
    if (index < 0 || index >= static_cast<double>(vertices))
      in.fail("the vertex index " + std::to_string(std::llround(index)) + " is out of range: there are " +
              std::to_string(vertices) + " vertices");
    v = static_cast<std::size_t>(index);
  }
  return polygon;
}

void read_element(const std::string& path, const Element& e, Data& in, std::uint64_t vertices, PolygonSoup& soup) {
  const Role role = role_of(path, e);
  if (e.properties.empty()) return;  // its items hold nothing, whatever their count
  const std::size_t least = item_bytes(e, in);
  if (e.count > in.room(least))
    fail(path, e.named() + " has " + std::to_string(e.count) + " items, more than the " +
                   std::to_string(in.bytes_left()) + " bytes left can hold (an item takes at least " +
                   std::to_string(least) + ")");
  const std::string item = "element '" + e.name + "' item";
  const auto count = static_cast<std::size_t>(e.count);
  if (role.kind == Role::Vertex) soup.points.reserve(soup.points.size() + count);
  if (role.kind == Role::Face) soup.polygons.reserve(soup.polygons.size() + count);
  double xyz[3] = {0, 0, 0};
  std::vector<std::size_t> polygon;
  for (std::size_t i = 0; i < count; ++i) {
    if (role.kind == Role::Vertex) in.set_item("vertex", soup.points.size());
    if (role.kind == Role::Face) in.set_item("face", soup.polygons.size());
    if (role.kind == Role::Other) in.set_item(item, i);
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const Property& p = e.properties[k];
      if (role.kind == Role::Face && k == role.indices) {
        polygon = read_polygon(in, p, vertices);
      } else if (p.list_size) {
        in.skip(p.type, read_list_size(in, p));
      } else {
        const double value = in.read(p.type);
        if (role.kind != Role::Vertex || (k != role.x && k != role.y && k != role.z)) continue;
        if (!std::isfinite(value)) in.fail("the coordinate " + p.name + " is not a finite number");
        xyz[k == role.x ? 0 : k == role.y ? 1 : 2] = value;
      }
    }
    if (role.kind == Role::Vertex) soup.points.emplace_back(xyz[0], xyz[1], xyz[2]);
    if (role.kind == Role::Face) soup.polygons.push_back(std::move(polygon));
  }
}

}  // namespace

PolygonSoup read_ply(const std::string& path, std::string_view data) {
  const Header header = read_header(path, data);
  std::uint64_t vertices = 0;  // over all "vertex" elements (saturated)
  for (const Element& e : header.elements)
    if (e.name == "vertex" || e.name == "vertices")
      vertices = e.count > std::numeric_limits<std::uint64_t>::max() - vertices
                     ? std::numeric_limits<std::uint64_t>::max()
                     : vertices + e.count;
  PolygonSoup soup;
  Data in(path, data, header);
  for (const Element& e : header.elements) read_element(path, e, in, vertices, soup);
  return soup;
}

}  // namespace sage::geometry::mesh
