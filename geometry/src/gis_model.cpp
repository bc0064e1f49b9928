#include <sage/geometry/gis_model.hpp>
#include <sage/geometry/gis_reader.hpp>
#include <sage/geometry/polygon_brep.hpp>
#include <sage/geometry/polygon_csg.hpp>
#include <sage/geometry/polygon_validation.hpp>
#include <sage/geometry/well_formedness.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

namespace sage::geometry {

namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
}

// Does a .json file hold GeoJSON rather than a sage model? Its top-level
// "type" says so ("FeatureCollection", "Feature", or a geometry type).
bool looks_like_geojson(const std::string& path) {
  std::ifstream in(path);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  for (const char* type : {"\"FeatureCollection\"", "\"Feature\"", "\"Polygon\"", "\"MultiPolygon\""})
    if (head.find(type) != std::string::npos && head.find("\"type\"") != std::string::npos) return true;
  return false;
}

Bounds bounds_of(const PolygonSet& set) {
  Bounds b{{1e300, 1e300, 0}, {-1e300, -1e300, 0}};
  set.for_each_ring([&b](const Ring& r) {
    for (const auto& p : r.points)
      for (int i = 0; i < 2; ++i) {
        b.min[i] = std::min(b.min[i], p[i]);
        b.max[i] = std::max(b.max[i], p[i]);
      }
  });
  // A margin of 5% of the diagonal, so the field outside shows too.
  const double margin = 0.05 * std::hypot(b.max[0] - b.min[0], b.max[1] - b.min[1]);
  for (int i = 0; i < 2; ++i) {
    b.min[i] -= margin;
    b.max[i] += margin;
  }
  return b;
}

}  // namespace

bool is_gis_path(const std::string& path) {
  for (const char* ext : {".geojson", ".shp", ".gpkg", ".gml", ".kml", ".fgb", ".sqlite", ".tab", ".mif"})
    if (ends_with(path, ext)) return true;
  return ends_with(path, ".json") && looks_like_geojson(path);
}

Model load_gis(const std::string& path, const LoadOptions& options) {
  GisPolygons gis = read_gis_polygons(path, options);
  const ValidationReport report = validate_polygons(gis.polygons, path, options.repair);

  Model m;
  m.source = path;
  m.dimension = 2;
  m.rfunction = options.rfunction.value_or(RSystem::r0());
  m.bounds = bounds_of(gis.polygons);
  std::size_t holes = 0;
  for (const auto& p : gis.polygons.polygons) holes += p.holes.size();
  m.name = std::to_string(gis.polygons.polygons.size()) + " polygon(s), " + std::to_string(holes) + " hole(s), " +
           std::to_string(gis.polygons.edge_count()) + " edges";
  m.notes.push_back("coordinates: " + gis.crs);
  m.crs_wkt = gis.crs_wkt;
  for (const auto& n : gis.notes) m.notes.push_back(n);
  m.warnings = gis.warnings;
  for (const auto& n : report.notes()) m.notes.push_back("validation: " + n);
  if (report.notes().empty()) m.notes.push_back("validation: no defects found");
  m.primitives.push_back({"", "edges", std::to_string(gis.polygons.edge_count()) + " edges"});

  if (options.method == "csg") {
    CsgStatistics stats;
    m.field = polygon_csg(gis.polygons, m.rfunction, &stats);
    m.notes.push_back("method: well-formed CSG by the decreasing convex hull, " + std::to_string(stats.halfplanes) +
                      " edge halfplanes (each edge once) and " + std::to_string(stats.bridges) +
                      " pocket bridges, pocket depth " + std::to_string(stats.depth) + ", " + m.rfunction.name());
    if (options.certify) {
      const double band = 1e-3 * std::hypot(m.bounds->max[0] - m.bounds->min[0], m.bounds->max[1] - m.bounds->min[1]);
      // R-functions take the sign of min/max of their arguments, so the
      // formula has the same zeros under every system; its min/max form
      // prunes (tape_specialization.hpp) and is proved fastest.
      const Expr same_zeros =
          m.rfunction == RSystem::min_max() ? m.field : polygon_csg(gis.polygons, RSystem::min_max());
      m.notes.push_back(certify_no_spurious_zeros(same_zeros, gis.polygons, *m.bounds, band).text +
                        " (proved on the min/max form of the formula: the same zeros under every R-function system)");
    }
  } else if (options.method == "brep") {
    m.field = polygon_brep(gis.polygons, m.rfunction);
    if (options.orthogonalize)
      m.notes.push_back(
          "--orthogonalize has no effect on polygon edges: their trimming disks already meet them "
          "at right angles");
    m.notes.push_back("method: trimmed-edge B-rep (smooth normalized trimming, " + m.rfunction.name() +
                      " gluing, exact point membership sign)");
  } else {
    throw ModelError(path + ": unknown method \"" + options.method + "\" (expected csg or brep)");
  }
  return m;
}

}  // namespace sage::geometry
