// sage's OFF and PLY readers (geometry/src/off_ply_reader.hpp):
//  - on the test meshes (OFF) and on PLY files made from them (ASCII,
//    binary little and big endian, CGAL's writer and ours) they give the
//    points and polygons CGAL::IO::read_polygon_soup gives, exactly;
//  - PLY of any numeric types, OFF variants (comments, colours, CRLF);
//  - the seven reproducers of CGAL's bugs (fuzz/regressions/mesh/) and
//    malformed files of our own are ModelErrors naming the file, the place
//    and what is wrong, in milliseconds and without a large allocation
//    (operator new is watched below).

#include "../../geometry/src/off_ply_reader.hpp"

#include <sage/geometry/mesh_model.hpp>

#include <CGAL/IO/polygon_soup_io.h>
#include <gtest/gtest.h>
#include <test_files.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <new>
#include <sstream>
#include <string>
#include <vector>

// ---- allocation watch -------------------------------------------------------
// Every operator new of this test program goes through malloc as usual;
// while a watch is on, the largest request and the total are recorded.
namespace {
std::atomic<bool> g_watching{false};
std::atomic<std::size_t> g_largest{0}, g_total{0};
}  // namespace

void* operator new(std::size_t n) {
  if (g_watching.load(std::memory_order_relaxed)) {
    g_total += n;
    std::size_t seen = g_largest.load();
    while (n > seen && !g_largest.compare_exchange_weak(seen, n)) {
    }
  }
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return ::operator new(n); }
// The nothrow forms too: the replaced deletes below free what they return.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return std::malloc(n ? n : 1); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return std::malloc(n ? n : 1); }
// Not inlined: GCC would see free() of what operator new returned
// (-Wmismatched-new-delete).
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace {

namespace fs = std::filesystem;
using sage::geometry::ModelError;
using sage::geometry::mesh::Point;
using sage::geometry::mesh::PolygonSoup;
using sage::geometry::mesh::read_off;
using sage::geometry::mesh::read_ply;
using Polygons = std::vector<std::vector<std::size_t>>;

class AllocationWatch {
 public:
  AllocationWatch() : start_(std::chrono::steady_clock::now()) {
    g_largest = 0;
    g_total = 0;
    g_watching = true;
  }
  ~AllocationWatch() { g_watching = false; }
  std::size_t largest() const { return g_largest; }
  std::size_t total() const { return g_total; }
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_;
};

std::string write_file(const std::string& name, const std::string& data) {
  const fs::path p = sage::test::scratch_dir() / name;
  std::ofstream(p, std::ios::binary) << data;
  return p.string();
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// read_off or read_ply by the name's extension.
PolygonSoup read(const std::string& name, const std::string& data) {
  return name.ends_with(".ply") ? read_ply(name, data) : read_off(name, data);
}

// Expects a ModelError "NAME: ..." holding every piece, quickly and with
// little memory (the file's data is already in memory).
void expect_error(const std::string& name, const std::string& data, std::initializer_list<std::string> pieces) {
  SCOPED_TRACE(name);
  const AllocationWatch watch;
  try {
    read(name, data);
    ADD_FAILURE() << "no error for " << name;
  } catch (const ModelError& e) {
    const std::string what = e.what();
    std::cout << "[reader error] " << what << "\n";
    EXPECT_EQ(what.rfind(name + ": ", 0), 0u) << what;
    for (const auto& piece : pieces)
      EXPECT_NE(what.find(piece), std::string::npos) << "'" << piece << "' not in: " << what;
  }
  EXPECT_LT(watch.largest(), 64u * 1024) << "largest allocation";
  EXPECT_LT(watch.total(), 1024u * 1024) << "total allocated";
  EXPECT_LT(watch.seconds(), 1.0);
}

// The exact equality of two soups.
void expect_same(const PolygonSoup& ours, const std::vector<Point>& points, const Polygons& polygons) {
  ASSERT_EQ(ours.points.size(), points.size());
  ASSERT_EQ(ours.polygons.size(), polygons.size());
  for (std::size_t v = 0; v < points.size(); ++v)
    ASSERT_TRUE(ours.points[v].x() == points[v].x() && ours.points[v].y() == points[v].y() &&
                ours.points[v].z() == points[v].z())
        << "vertex " << v << ": " << ours.points[v] << " vs " << points[v];
  for (std::size_t f = 0; f < polygons.size(); ++f) ASSERT_EQ(ours.polygons[f], polygons[f]) << "face " << f;
}

// CGAL's soup of a file.
void cgal_soup(const std::string& path, std::vector<Point>& points, Polygons& polygons) {
  points.clear();
  polygons.clear();
  ASSERT_TRUE(CGAL::IO::read_polygon_soup(path, points, polygons)) << path;
}

// ---- a PLY writer of any types ------------------------------------------------

struct PlyStyle {
  std::string format = "ascii";  // or binary_little_endian, binary_big_endian
  std::string coordinate = "double", size_type = "uchar", index_type = "int";
  bool extras = false;  // a colour and a list per vertex, an element before the faces, a face flag
  bool crlf = false;    // header lines end with \r\n
};

std::size_t type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "double" || t == "float64") return 8;
  return 4;
}

// One value of type t: as text (ASCII) or as the type's bytes.
void put(std::ostream& out, const PlyStyle& s, const std::string& t, double v) {
  if (s.format == "ascii") {
    if (t == "float" || t == "float32")
      out << std::setprecision(9) << static_cast<float>(v) << " ";
    else if (t == "double" || t == "float64")
      out << std::setprecision(17) << v << " ";
    else
      out << static_cast<long long>(v) << " ";
    return;
  }
  unsigned char b[8];
  const std::size_t n = type_size(t);
  const auto copy = [&](auto x) { std::memcpy(b, &x, sizeof x); };
  if (t == "float" || t == "float32")
    copy(static_cast<float>(v));
  else if (t == "double" || t == "float64")
    copy(v);
  else if (t == "char" || t == "int8")
    copy(static_cast<std::int8_t>(v));
  else if (t == "uchar" || t == "uint8")
    copy(static_cast<std::uint8_t>(v));
  else if (t == "short" || t == "int16")
    copy(static_cast<std::int16_t>(v));
  else if (t == "ushort" || t == "uint16")
    copy(static_cast<std::uint16_t>(v));
  else if (t == "int" || t == "int32")
    copy(static_cast<std::int32_t>(v));
  else
    copy(static_cast<std::uint32_t>(v));
  static_assert(std::endian::native == std::endian::little);
  if (s.format == "binary_big_endian") std::reverse(b, b + n);
  out.write(reinterpret_cast<const char*>(b), static_cast<std::streamsize>(n));
}

void end_item(std::ostream& out, const PlyStyle& s) {
  if (s.format == "ascii") out << "\n";
}

std::string ply_text(const std::vector<Point>& points, const Polygons& polygons, const PlyStyle& s) {
  std::ostringstream out;
  const std::string nl = s.crlf ? "\r\n" : "\n";
  out << "ply" << nl << "format " << s.format << " 1.0" << nl << "comment made by mesh_reader_test" << nl;
  out << "element vertex " << points.size() << nl;
  for (const char* c : {"x", "y", "z"}) out << "property " << s.coordinate << " " << c << nl;
  if (s.extras)
    out << "property uchar red" << nl << "property uchar green" << nl << "property uchar blue" << nl
        << "property list uchar float texcoord" << nl << "element edge 2" << nl << "property int vertex1" << nl
        << "property int vertex2" << nl;
  out << "element face " << polygons.size() << nl;
  if (s.extras) out << "property uchar flags" << nl;
  out << "property list " << s.size_type << " " << s.index_type << " vertex_indices" << nl;
  out << "obj_info no object" << nl << "end_header" << nl;
  for (std::size_t v = 0; v < points.size(); ++v) {
    for (double c : {points[v].x(), points[v].y(), points[v].z()}) put(out, s, s.coordinate, c);
    if (s.extras) {
      for (int k = 0; k < 3; ++k) put(out, s, "uchar", static_cast<double>((v * 7 + k) % 256));
      put(out, s, "uchar", static_cast<double>(v % 3));
      for (std::size_t k = 0; k < v % 3; ++k) put(out, s, "float", 0.25 * static_cast<double>(k));
    }
    end_item(out, s);
  }
  if (s.extras)
    for (int e = 0; e < 2; ++e) {
      put(out, s, "int", e);
      put(out, s, "int", e + 1);
      end_item(out, s);
    }
  for (const auto& polygon : polygons) {
    if (s.extras) put(out, s, "uchar", 1);
    put(out, s, s.size_type, static_cast<double>(polygon.size()));
    for (std::size_t i : polygon) put(out, s, s.index_type, static_cast<double>(i));
    end_item(out, s);
  }
  return out.str();
}

const char* const kMeshes[] = {"joint.off", "pinion.off", "elephant.off", "fandisk.off"};

// ---- equality with CGAL's readers ----------------------------------------------

TEST(MeshReaders, OffEqualsCgalOnTheTestMeshes) {
  for (const char* name : kMeshes) {
    SCOPED_TRACE(name);
    const std::string path = sage::test::test_data(std::string("meshes/") + name);
    std::vector<Point> points;
    Polygons polygons;
    cgal_soup(path, points, polygons);
    const PolygonSoup ours = read_off(path, read_file(path));
    expect_same(ours, points, polygons);
    std::cout << name << ": " << points.size() << " vertices, " << polygons.size() << " faces, equal\n";
  }
}

TEST(MeshReaders, PlyEqualsCgalOnTheTestMeshesAsciiAndBinary) {
  std::vector<PlyStyle> styles;
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"})
    for (const char* coordinate : {"double", "float"})
      for (bool extras : {false, true}) {
        PlyStyle s;
        s.format = format;
        s.coordinate = coordinate;
        s.index_type = extras ? "uint" : "int";
        s.size_type = extras ? "int" : "uchar";
        s.extras = extras;
        s.crlf = extras;
        styles.push_back(s);
      }
  for (const char* name : kMeshes) {
    const std::string off = sage::test::test_data(std::string("meshes/") + name);
    std::vector<Point> points;
    Polygons polygons;
    cgal_soup(off, points, polygons);
    // CGAL's own writer, ASCII and binary.
    for (bool binary : {false, true}) {
      SCOPED_TRACE(std::string(name) + (binary ? " CGAL binary" : " CGAL ascii"));
      const std::string ply =
          (sage::test::scratch_dir() / (std::string("cgal_") + (binary ? "b_" : "a_") + name + ".ply")).string();
      ASSERT_TRUE(CGAL::IO::write_polygon_soup(ply, points, polygons,
                                               CGAL::parameters::use_binary_mode(binary).stream_precision(17)));
      std::vector<Point> cgal_points;
      Polygons cgal_polygons;
      cgal_soup(ply, cgal_points, cgal_polygons);
      expect_same(read_ply(ply, read_file(ply)), cgal_points, cgal_polygons);
      expect_same(read_ply(ply, read_file(ply)), points, polygons);
    }
    // Ours, in every format, with doubles and floats, with and without
    // properties and an element to skip.
    for (const PlyStyle& s : styles) {
      SCOPED_TRACE(std::string(name) + " " + s.format + " " + s.coordinate + (s.extras ? " extras" : ""));
      const std::string ply =
          write_file(std::string(name) + "_" + s.format + s.coordinate + (s.extras ? "_extras" : "") + ".ply",
                     ply_text(points, polygons, s));
      std::vector<Point> cgal_points;
      Polygons cgal_polygons;
      cgal_soup(ply, cgal_points, cgal_polygons);
      const PolygonSoup ours = read_ply(ply, read_file(ply));
      expect_same(ours, cgal_points, cgal_polygons);
      if (s.coordinate == "double") expect_same(ours, points, polygons);
    }
  }
}

// A tetrahedron, outward.
const std::vector<Point> kTet = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const Polygons kTetFaces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

TEST(MeshReaders, PlyOfEveryNumericType) {
  // Coordinates and indices of any type (CGAL reads only float and double
  // coordinates and int or uint indices).
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"})
    for (const char* coordinate :
         {"char", "uchar", "short", "ushort", "int", "uint", "float", "double", "int8", "uint16", "float32", "float64"})
      for (const char* index : {"char", "uchar", "int16", "ushort", "int", "uint32"}) {
        PlyStyle s;
        s.format = format;
        s.coordinate = coordinate;
        s.index_type = index;
        s.size_type = index;
        s.extras = std::string(index) == "uchar";
        SCOPED_TRACE(std::string(format) + " " + coordinate + " " + index);
        const std::string text = ply_text(kTet, kTetFaces, s);
        expect_same(read_ply("tet.ply", text), kTet, kTetFaces);
      }
  // Two vertex and two face elements are read in turn, as CGAL does.
  const std::string two =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar uint vertex_index\nelement vertices 2\nproperty double z\n"
      "property double y\nproperty double x\nelement faces 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n3 0 2 1\n3 0 1 3\n0 1 0\n1 0 0\n3 0 3 2\n3 1 2 3\n";
  expect_same(read_ply("two.ply", two), kTet, kTetFaces);
  const std::string path = write_file("two.ply", two);
  std::vector<Point> points;
  Polygons polygons;
  cgal_soup(path, points, polygons);
  expect_same(read_ply(path, two), points, polygons);
}

TEST(MeshReaders, OffVariants) {
  // Each variant, and whether CGAL reads it too: it wants the edge count,
  // and reads texture coordinates without colours (STOFF) at an index it
  // never set.
  const std::vector<std::pair<std::string, bool>> variants = {
      {"OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", true},
      // Comments, blank lines, counts on the keyword's line, no edge count,
      // no newline at the end.
      {"# a tetrahedron\nOFF 4 4\n\n# vertices\n0 0 0  # the origin\n1 0 0\n\n0 1 0\n0 0 1\n"
       "# faces\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3",
       false},
      // Windows line ends, tabs, signs and exponents.
      {"OFF\r\n4 4 0\r\n0 0 0\r\n+1 -0 0\r\n0e0\t1.0\t0\r\n0 0 1E0\r\n3 0 2 1\r\n3 0 1 3\r\n3 0 3 2\r\n3 1 2 3\r\n",
       true},
      // COFF: colours after the vertices and the faces (RGBA, RGB, an index).
      {"COFF\n4 4 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n0 0 1 1 1 1 1\n"
       "3 0 2 1 255 0 0\n3 0 1 3 0.5 0.5 0.5 1\n3 0 3 2 7\n3 1 2 3 0 0 0\n",
       true},
      // NOFF: normals; STOFF: texture coordinates.
      {"NOFF\n4 4 0\n0 0 0 -1 -1 -1\n1 0 0 1 0 0\n0 1 0 0 1 0\n0 0 1 0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
       true},
      {"STOFF\n4 4 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n0 0 1 1 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", false},
  };
  for (std::size_t i = 0; i < variants.size(); ++i) {
    SCOPED_TRACE("variant " + std::to_string(i));
    const auto& [text, cgal_reads_it] = variants[i];
    expect_same(read_off("tet.off", text), kTet, kTetFaces);
    if (!cgal_reads_it) continue;
    const std::string path = write_file("variant" + std::to_string(i) + ".off", text);
    std::vector<Point> points;
    Polygons polygons;
    cgal_soup(path, points, polygons);
    expect_same(read_off(path, text), points, polygons);
  }
}

// ---- the fuzzer's reproducers of CGAL's bugs -------------------------------------

// fuzz/regressions/mesh/NAME through load_mesh: its first byte picks the
// format (fuzz/mesh.cpp), the rest is the file.
void expect_reproducer_error(const std::string& name, std::initializer_list<std::string> pieces) {
  SCOPED_TRACE(name);
  const std::string input = read_file(std::string(SAGE_SOURCE_DIR) + "/fuzz/regressions/mesh/" + name);
  ASSERT_FALSE(input.empty());
  const char* const extensions[] = {".off", ".stl", ".obj", ".ply"};
  const std::string path = write_file(name + extensions[input[0] & 3], input.substr(1));
  const AllocationWatch watch;
  try {
    sage::geometry::load_mesh(path, {});
    ADD_FAILURE() << "no error for " << name;
  } catch (const ModelError& e) {
    const std::string what = e.what();
    std::cout << "[reproducer] " << what << "\n";
    EXPECT_EQ(what.rfind(path + ": ", 0), 0u) << what;
    for (const auto& piece : pieces)
      EXPECT_NE(what.find(piece), std::string::npos) << "'" << piece << "' not in: " << what;
  }
  EXPECT_LT(watch.largest(), 64u * 1024) << "largest allocation";
  EXPECT_LT(watch.total(), 1024u * 1024) << "total allocated";
  EXPECT_LT(watch.seconds(), 1.0);
}

TEST(MeshReaders, FuzzReproducersOfCgalBugsAreErrors) {
  expect_reproducer_error("ply_property_before_element", {"line 3", "'property' line before any 'element'"});
  expect_reproducer_error("ply_vertex_without_properties", {"element 'vertex' (line 3)", "no property 'x'"});
  expect_reproducer_error("ply_element_without_properties",
                          {"line 3", "element 'halfedge'", "count '-1' is not a non-negative integer"});
  expect_reproducer_error("ply_list_of_4e9_indices",
                          {"face 0 (line 6)", "list 'vertex_indices' has 4000000000 items", "bytes left"});
  expect_reproducer_error("off_1e8_faces", {"line 2", "100000000 faces", "cannot fit in the"});
  expect_reproducer_error("off_face_of_4e9_vertices",
                          {"line 6", "face 0 has 4000000000 vertices", "holds only 3 number(s)"});
  expect_reproducer_error("off_negative_face_size", {"line 6", "face 0 has -1 vertices", "at least 3"});
}

// ---- malformed files of our own ---------------------------------------------------

const std::string kOffHeader = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const std::string kPadding = "# padding, so that the counts fit in the bytes left\n";

TEST(MeshReaders, MalformedOff) {
  expect_error("empty.off", "", {"empty", "no OFF header"});
  expect_error("comments.off", "# only\n\n# comments\n", {"empty"});
  expect_error("garbage.off", "this is not an OFF file\n", {"line 1", "not an OFF file", "'this'"});
  expect_error("binary.off", std::string("OFF BINARY\n\0\0\0\4", 15),
               {"line 1", "binary OFF is not supported", "convert"});
  expect_error("homogeneous.off", "4OFF\n1 0 0\n0 0 0 1\n", {"line 1", "'4OFF'", "not supported"});
  expect_error("skel.off", "SKEL\n2 1\n0 0 0\n1 0 0\n2 0 1\n", {"line 1", "SKEL", "not a surface mesh"});
  expect_error("no_counts.off", "OFF\n", {"counts are missing"});
  expect_error("one_count.off", "OFF\n4\n", {"line 2", "expected the counts", "1 word(s)"});
  expect_error("bad_count.off", "OFF\n4 x 0\n", {"line 2", "face count 'x'", "not a non-negative integer"});
  expect_error("negative_count.off", "OFF\n-4 4 0\n", {"line 2", "vertex count '-4'"});
  expect_error("huge_count.off", "OFF\n99999999999999999999 1 0\n", {"line 2", "vertex count '9999"});
  expect_error("too_many_vertices.off", "OFF\n1000000000000000000 0 0\n0 0 0\n",
               {"line 2", "1000000000000000000 vertices cannot fit in the 6 bytes"});
  expect_error("too_many_faces.off", kOffHeader + "3\n", {"line 2", "4 faces", "cannot fit in the 26 bytes"});
  expect_error("truncated_vertices.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n" + kPadding,
               {"the file ends after 2 of its 4 vertices"});
  expect_error("truncated_faces.off", kOffHeader + "3 0 2 1\n3 0 1 3\n" + kPadding,
               {"the file ends after 2 of its 4 faces"});
  expect_error("short_vertex.off", "OFF\n4 0 0\n0 0 0\n1 0\n0 1 0\n0 0 1\n" + kPadding,
               {"line 4", "vertex 1 has 2 number(s), expected x y z"});
  expect_error("bad_number.off", "OFF\n4 0 0\n0 0 0\n1 0 zero\n0 1 0\n0 0 1\n",
               {"line 4", "vertex 1: 'zero' is not a number"});
  expect_error("bad_extra.off", "OFF\n4 0 0\n0 0 0\n1 0 0 red\n0 1 0\n0 0 1\n",
               {"line 4", "vertex 1: 'red' is not a number"});
  expect_error("infinite.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1e999 0\n0 0 1\n",
               {"line 5", "vertex 2: the coordinate '1e999' is not a finite number"});
  expect_error("nan.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1 0\nnan 0 1\n",
               {"line 6", "vertex 3: the coordinate 'nan' is not a finite number"});
  expect_error("index_out_of_range.off", kOffHeader + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 9\n",
               {"line 10", "face 3 refers to vertex 9, but there are only 4 vertices (0 to 3)"});
  expect_error("negative_index.off", kOffHeader + "3 0 2 1\n3 0 -1 3\n3 0 3 2\n3 1 2 3\n",
               {"line 8", "face 1 refers to vertex -1"});
  expect_error("fractional_index.off", kOffHeader + "3 0 2 1.5\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
               {"line 7", "face 0: the vertex index '1.5' is not an integer"});
  expect_error("bad_face_count.off", kOffHeader + "three 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
               {"line 7", "face 0: its vertex count 'three' is not an integer"});
  expect_error("missing_index.off", kOffHeader + "4 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
               {"line 7", "face 0 has 4 vertices, but its line holds only 3 number(s)"});
  expect_error("bad_colour.off", kOffHeader + "3 0 2 1 red\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
               {"line 7", "face 0 (colour): 'red' is not a number"});
  expect_error("binary_junk.off", "OFF\n1 0 0\n\x01\xff\x80 0 0\n",
               {"line 3", "vertex 0: '\\x01\\xff\\x80' is not a number"});
}

const std::string kPlyTet =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kTetVertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";

TEST(MeshReaders, MalformedPlyHeader) {
  expect_error("empty.ply", "", {"the file is empty"});
  expect_error("not_ply.ply", "PLY\nformat ascii 1.0\nend_header\n", {"line 1", "not a PLY file"});
  expect_error("no_format.ply", "ply\nelement vertex 0\nend_header\n", {"line 2", "'element' before the 'format'"});
  expect_error("unknown_format.ply", "ply\nformat binary 1.0\nend_header\n", {"line 2", "unknown format 'binary'"});
  expect_error("two_formats.ply", "ply\nformat ascii 1.0\nformat ascii 1.0\nend_header\n",
               {"line 3", "a second 'format' line"});
  expect_error("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 0\n",
               {"header ends at line 3 without an 'end_header'"});
  expect_error("keyword.ply", "ply\nformat ascii 1.0\nelemnt vertex 1\nend_header\n",
               {"line 3", "unknown header keyword 'elemnt'"});
  expect_error("element_line.ply", "ply\nformat ascii 1.0\nelement vertex\nend_header\n",
               {"line 3", "expected 'element NAME COUNT'"});
  expect_error("element_count.ply", "ply\nformat ascii 1.0\nelement vertex many\nend_header\n",
               {"line 3", "element 'vertex': its count 'many' is not a non-negative integer"});
  expect_error("huge_count.ply", "ply\nformat ascii 1.0\nelement vertex 18446744073709551616\nend_header\n",
               {"line 3", "its count '18446744073709551616'"});
  expect_error("property_first.ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 1\nend_header\n0\n",
               {"line 3", "a 'property' line before any 'element' line"});
  expect_error("unknown_type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float16 x\nend_header\n",
               {"line 4", "unknown property type 'float16'"});
  expect_error("unknown_item_type.ply",
               "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar index vertex_indices\nend_header\n",
               {"line 4", "unknown property type 'index'"});
  expect_error("float_size.ply",
               "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n",
               {"line 4", "a list's size type must be an integer type, not 'float'"});
  expect_error("property_line.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float\nend_header\n",
               {"line 4", "expected 'property TYPE NAME'"});
  expect_error("list_line.ply",
               "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar vertex_indices\nend_header\n",
               {"line 4", "expected 'property list SIZETYPE ITEMTYPE NAME'"});
  expect_error("no_z.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n",
               {"element 'vertex' (line 3) has no property 'z'"});
  expect_error("list_x.ply",
               "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\nproperty float y\n"
               "property float z\nend_header\n",
               {"element 'vertex' (line 3): its property 'x' is a list, not a number"});
  expect_error("no_indices.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex\nend_header\n",
               {"element 'face' (line 3) has no list 'vertex_indices' (nor 'vertex_index')"});
  expect_error("float_indices.ply",
               "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n",
               {"element 'face' (line 3): its property 'vertex_indices' is not a list of integers"});
  expect_error("scalar_indices.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty int vertex_indices\nend_header\n",
               {"its property 'vertex_indices' is not a list of integers"});
}

TEST(MeshReaders, MalformedAsciiPly) {
  expect_error("too_many_vertices.ply",
               "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
               "property float z\nend_header\n0 0 0\n",
               {"element 'vertex' (line 3) has 4000000000 items, more than the 6 bytes left can hold", "at least 6"});
  expect_error("too_many_items.ply",
               "ply\nformat ascii 1.0\nelement flags 18446744073709551615\nproperty uchar f\nend_header\n1\n",
               {"element 'flags' (line 3) has 18446744073709551615 items"});
  expect_error("truncated.ply", kPlyTet + kTetVertices + "3 0 2 1\n3 0 1 3\n",
               {"face 2 (end of file): the file ends where a uchar was expected"});
  expect_error("truncated_list.ply", kPlyTet + kTetVertices + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2\n",
               {"face 3 (end of file): the file ends where an int was expected"});
  expect_error("bad_number.ply", kPlyTet + "0 0 0\n1 0 0\n0 1 zero\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
               {"vertex 2 (line 12): 'zero' is not a number (float)"});
  expect_error("nan.ply", kPlyTet + "0 0 0\n1 0 0\n0 1 nan\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
               {"vertex 2 (line 12): the coordinate z is not a finite number"});
  expect_error("fractional_index.ply", kPlyTet + kTetVertices + "3 0 2 1\n3 0 1 3\n3 0 3 2.5\n3 1 2 3\n",
               {"face 2 (line 16): '2.5' is not an integer (int)"});
  expect_error("out_of_type.ply", kPlyTet + kTetVertices + "3 0 2 1\n300 0 1 3\n3 0 3 2\n3 1 2 3\n",
               {"face 1 (line 15): '300' is out of the range of uchar (0 to 255)"});
  expect_error("index_out_of_range.ply", kPlyTet + kTetVertices + "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 4\n",
               {"face 3 (line 17): the vertex index 4 is out of range: there are 4 vertices"});
  expect_error("negative_index.ply", kPlyTet + kTetVertices + "3 0 2 1\n3 0 -1 3\n3 0 3 2\n3 1 2 3\n",
               {"face 1 (line 15): the vertex index -1 is out of range"});
  expect_error("negative_size.ply",
               "ply\nformat ascii 1.0\nelement face 1\nproperty list char int vertex_indices\nend_header\n-3 0 1 2\n",
               {"face 0 (line 6): the list 'vertex_indices' has a negative size, -3"});
  expect_error("long_list.ply",
               "ply\nformat ascii 1.0\nelement face 1\nproperty list ushort int vertex_indices\nend_header\n"
               "60000 0 1 2\n",
               {"face 0 (line 6): the list 'vertex_indices' has 60000 items, more than the 7 bytes left"});
  expect_error("skipped_list.ply",
               "ply\nformat ascii 1.0\nelement material 1\nproperty list uint float colours\nend_header\n"
               "4000000000 1 1 1\n",
               {"element 'material' item 0 (line 6): the list 'colours' has 4000000000 items"});
}

// The binary tetrahedron with the bytes at [at, at + n) replaced.
std::string binary_tet(const PlyStyle& s, std::size_t from_end, const std::string& bytes) {
  std::string text = ply_text(kTet, kTetFaces, s);
  text.replace(text.size() - from_end, bytes.size(), bytes);
  return text;
}

TEST(MeshReaders, MalformedBinaryPly) {
  PlyStyle le;
  le.format = "binary_little_endian";
  le.coordinate = "float";
  PlyStyle be = le;
  be.format = "binary_big_endian";
  const std::string ok = ply_text(kTet, kTetFaces, le);
  expect_same(read_ply("tet.ply", ok), kTet, kTetFaces);
  // The last face's last index (4 bytes from the end): out of range.
  expect_error("index_le.ply", binary_tet(le, 4, std::string("\x04\0\0\0", 4)),
               {"face 3 (byte ", "the vertex index 4 is out of range: there are 4 vertices"});
  expect_error("index_be.ply", binary_tet(be, 4, std::string("\0\0\x01\0", 4)),
               {"face 3 (byte ", "the vertex index 256 is out of range"});
  // The last face's size (13 bytes from the end): 2, or 255.
  expect_error("long_face.ply", binary_tet(le, 13, "\xff"),
               {"face 3 (byte ", "the list 'vertex_indices' has 255 items, more than the 12 bytes left"});
  // Vertex 3's z (the faces take 4 x 13 bytes): a NaN.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  expect_error("nan.ply", binary_tet(le, 52 + 4, std::string(reinterpret_cast<const char*>(&nan), 4)),
               {"vertex 3 (byte ", "the coordinate z is not a finite number"});
  // Cut: the faces no longer fit, or the list does not.
  expect_error("cut_faces.ply", ok.substr(0, ok.size() - 49),
               {"element 'face' (line 8) has 4 items, more than the 3 bytes left"});
  expect_error("cut_list.ply", ok.substr(0, ok.size() - 2), {"face 3 (byte ", "has 3 items, more than the 10 bytes"});
  // A 32-bit list size of 4e9.
  PlyStyle big = le;
  big.size_type = "uint";
  expect_error("4e9_indices.ply", binary_tet(big, 16, std::string("\0\x28\x6b\xee", 4)),
               {"face 3 (byte ", "'vertex_indices' has 4000000000 items"});
  // No vertex element: every index is out of range.
  const std::string cut =
      "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uchar uchar vertex_indices\n"
      "property int flags\nend_header\n" +
      std::string("\x03\0\0\0\x07\0", 6);
  expect_error("no_vertices.ply", cut, {"face 0 (byte ", "the vertex index 0 is out of range: there are 0 vertices"});
  const std::string cut_value =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty uchar x\nproperty uchar y\n"
      "property uchar z\nelement face 1\nproperty list uchar uchar vertex_indices\nproperty int flags\nend_header\n" +
      std::string("\0\0\0\1\0\0\0\1\0\x03\0\1\2\x07\0", 15);
  // A value cut in its middle: an int after a list that fits.
  expect_error("cut_int.ply", cut_value, {"face 0 (byte ", "the file ends in the middle of an int (2 of its 4 bytes)"});
}

TEST(MeshReaders, PlyElementsWithoutPropertiesAreSkipped) {
  // Items of nothing take no bytes, whatever their count.
  const std::string text = "ply\nformat ascii 1.0\nelement halfedge 18446744073709551615\n" +
                           kPlyTet.substr(kPlyTet.find("element vertex")) + kTetVertices +
                           "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const AllocationWatch watch;
  expect_same(read_ply("halfedges.ply", text), kTet, kTetFaces);
  EXPECT_LT(watch.seconds(), 1.0);
  EXPECT_GT(watch.total(), 0u);  // the watch sees the soup's allocations
}

// A face of fewer than 3 vertices is refused by the mesh loader, naming
// the face, and dropped by --repair (PMP::repair_polygon_soup), as it was
// for files CGAL read: the readers leave that decision to the loader.
TEST(MeshReaders, DegenerateFacesAreRefusedOrRepaired) {
  const std::string tetrahedron = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const std::map<std::string, std::string> files = {
      {"two_vertex_face.off", "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n2 0 1\n" + tetrahedron},
      {"two_vertex_face.ply",
       "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 5\nproperty list uchar int vertex_indices\nend_header\n" +
           kTetVertices + "2 0 1\n" + tetrahedron}};
  for (const auto& [name, data] : files) {
    SCOPED_TRACE(name);
    const std::string path = write_file(name, data);
    try {
      sage::geometry::load_mesh(path, {});
      ADD_FAILURE() << "no error without --repair";
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("face 0 is degenerate: it has 2 vertices"), std::string::npos) << e.what();
    }
    sage::geometry::LoadOptions repair;
    repair.repair = true;
    const sage::geometry::Model model = sage::geometry::load_mesh(path, repair);
    ASSERT_TRUE(model.surface);
    EXPECT_EQ(model.surface->triangles.size(), 4u);
  }
}

}  // namespace
