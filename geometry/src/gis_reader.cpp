#include <sage/geometry/gis_reader.hpp>

#include <cpl_error.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>

namespace sage::geometry {

namespace {

/// GDAL's own error text, without letting GDAL print to stderr.
class QuietGdal {
 public:
  QuietGdal() { CPLPushErrorHandler(CPLQuietErrorHandler); }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;
  static std::string last_message() {
    const char* m = CPLGetLastErrorMsg();
    return m && *m ? m : "no details from GDAL";
  }
};

struct GeometryDeleter {
  void operator()(OGRGeometry* g) const { OGRGeometryFactory::destroyGeometry(g); }
};
using GeometryPtr = std::unique_ptr<OGRGeometry, GeometryDeleter>;

std::string type_name(const OGRGeometry* g) { return OGRGeometryTypeToName(g->getGeometryType()); }

/// The polygons of g (Polygon, MultiPolygon, curves linearized, polygons of
/// a collection); throws for other geometry types.
std::vector<const OGRPolygon*> polygons_of(const OGRGeometry* g, const std::string& where) {
  std::vector<const OGRPolygon*> out;
  switch (wkbFlatten(g->getGeometryType())) {
    case wkbPolygon: out.push_back(g->toPolygon()); break;
    case wkbMultiPolygon:
      for (const OGRPolygon* p : *g->toMultiPolygon()) out.push_back(p);
      break;
    case wkbGeometryCollection:
      // MakeValid and unions may return polygons mixed with lines or points
      // of zero area; only the polygons bound a region.
      for (const OGRGeometry* part : *g->toGeometryCollection())
        if (wkbFlatten(part->getGeometryType()) == wkbPolygon || wkbFlatten(part->getGeometryType()) == wkbMultiPolygon)
          for (const OGRPolygon* p : polygons_of(part, where)) out.push_back(p);
      break;
    default: throw ModelError(where + ": geometry is " + type_name(g) + ", expected Polygon or MultiPolygon");
  }
  return out;
}

Ring ring_of(const OGRLinearRing* r, long long feature, int polygon, int ring) {
  Ring out;
  out.feature = feature;
  out.polygon = polygon;
  out.ring = ring;
  int n = r->getNumPoints();
  // OGR rings repeat the first point at the end; drop the repetition.
  if (n > 1 && r->getX(0) == r->getX(n - 1) && r->getY(0) == r->getY(n - 1)) --n;
  for (int i = 0; i < n; ++i) {
    out.points.push_back({r->getX(i), r->getY(i)});
    out.source_vertex.push_back(i);
  }
  return out;
}

/// `srs` as WKT2, the form that keeps every parameter and authority code.
std::string wkt_of(const OGRSpatialReference& srs) {
  char* text = nullptr;
  const char* const options[] = {"FORMAT=WKT2_2019", nullptr};
  if (srs.exportToWkt(&text, options) != OGRERR_NONE) text = nullptr;
  std::string wkt = text ? text : "";
  CPLFree(text);
  return wkt;
}

/// A local azimuthal equidistant projection centred on (lat, lon).
std::unique_ptr<OGRSpatialReference> local_projection(double lat, double lon) {
  auto srs = std::make_unique<OGRSpatialReference>();
  std::ostringstream proj;
  proj.precision(12);
  proj << "+proj=aeqd +lat_0=" << lat << " +lon_0=" << lon << " +x_0=0 +y_0=0 +datum=WGS84 +units=m +no_defs";
  if (srs->importFromProj4(proj.str().c_str()) != OGRERR_NONE)
    throw ModelError("cannot set up the projection " + proj.str() + ": " + QuietGdal::last_message());
  // PROJ calls it "unknown"; a name tells it apart in GIS tools and summaries.
  std::ostringstream name;
  name.precision(8);
  name << "sage local azimuthal equidistant, lat " << lat << ", lon " << lon;
  srs->SetProjCS(name.str().c_str());
  srs->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

using Geometries = std::vector<std::pair<long long, GeometryPtr>>;

/// True when every coordinate of the geometries is a possible longitude
/// and latitude in degrees.
bool within_lon_lat(const Geometries& geometries) {
  for (const auto& [i, g] : geometries) {
    OGREnvelope e;
    g->getEnvelope(&e);
    if (e.MinX < -180 || e.MaxX > 180 || e.MinY < -90 || e.MaxY > 90) return false;
  }
  return true;
}

/// Transforms longitude/latitude geometries (in `source_srs`) to a local
/// azimuthal equidistant projection; returns what was done, in words, and
/// sets `wkt` to the projection.
std::string project_lon_lat(const std::string& path, const OGRSpatialReference& source_srs, Geometries& geometries,
                            std::string& wkt) {
  OGREnvelope box;
  bool first = true;
  for (auto& [i, g] : geometries) {
    OGREnvelope e;
    g->getEnvelope(&e);
    if (first)
      box = e;
    else
      box.Merge(e);
    first = false;
  }
  const double lon = 0.5 * (box.MinX + box.MaxX), lat = 0.5 * (box.MinY + box.MaxY);
  std::unique_ptr<OGRSpatialReference> source(source_srs.Clone());
  source->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  const auto target = local_projection(lat, lon);
  std::unique_ptr<OGRCoordinateTransformation> transform(OGRCreateCoordinateTransformation(source.get(), target.get()));
  if (!transform) throw ModelError(path + ": cannot project the data: " + QuietGdal::last_message());
  for (auto& [i, g] : geometries)
    if (g->transform(transform.get()) != OGRERR_NONE)
      throw ModelError(path + ": feature " + std::to_string(i) + ": projection failed: " + QuietGdal::last_message());
  wkt = wkt_of(*target);
  std::ostringstream crs;
  crs.precision(8);
  crs << "longitude/latitude (" << (source_srs.GetName() ? source_srs.GetName() : "geographic")
      << ") projected to azimuthal equidistant centred on lat " << lat << ", lon " << lon << " (WGS84, metres)";
  return crs.str();
}

/// Brings the geometries into a plane in metres: longitude/latitude data is
/// projected, projected data kept. The source system is `user_crs` (--crs)
/// when given, else the layer's; data with neither is taken as planar, with
/// a warning when its coordinates could be degrees. Returns what was done,
/// and sets `wkt` to the plane's system (empty when there is none).
std::string project_to_plane(const std::string& path, const OGRSpatialReference* layer_srs,
                             const std::optional<std::string>& user_crs, Geometries& geometries,
                             std::vector<std::string>& warnings, std::string& wkt) {
  OGRSpatialReference given;
  std::string overridden;
  if (user_crs) {
    if (given.SetFromUserInput(user_crs->c_str()) != OGRERR_NONE)
      throw ModelError(path + ": --crs " + *user_crs + ": PROJ does not know this coordinate reference system (" +
                       QuietGdal::last_message() + "); give it as EPSG:XXXX, a PROJ string or WKT");
    if (layer_srs && layer_srs->GetName())
      overridden = std::string(", --crs in place of the file's ") + layer_srs->GetName();
    layer_srs = &given;
  }
  if (!layer_srs) {
    if (within_lon_lat(geometries))
      warnings.push_back(path +
                         ": no coordinate reference system, and every coordinate lies within longitude/latitude "
                         "ranges: if they are degrees, give --crs EPSG:4326 (the field is built as if they were "
                         "planar)");
    return "no coordinate reference system: coordinates used as is (assumed planar)";
  }
  if (layer_srs->IsGeographic()) return project_lon_lat(path, *layer_srs, geometries, wkt) + overridden;
  wkt = wkt_of(*layer_srs);
  return std::string(layer_srs->GetName() ? layer_srs->GetName() : "projected") + " (projected, used as is)" +
         overridden;
}

}  // namespace

GisPolygons read_gis_polygons(const std::string& path, const LoadOptions& options) {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  QuietGdal quiet;

  GDALDatasetUniquePtr dataset(
      GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!dataset) throw ModelError(path + ": GDAL cannot read it as vector data: " + QuietGdal::last_message());
  if (dataset->GetLayerCount() == 0) throw ModelError(path + ": no layers");
  OGRLayer* layer = options.layer ? dataset->GetLayerByName(options.layer->c_str()) : dataset->GetLayer(0);
  if (!layer) throw ModelError(path + ": no layer named \"" + *options.layer + "\"");
  if (options.where && layer->SetAttributeFilter(options.where->c_str()) != OGRERR_NONE)
    throw ModelError(path + ": --where \"" + *options.where + "\": " + QuietGdal::last_message());

  GisPolygons out;
  // Collect the selected features' geometries (owned copies).
  const std::set<long long> wanted(options.features.begin(), options.features.end());
  Geometries geometries;
  long long index = 0;
  layer->ResetReading();
  for (auto& feature : *layer) {
    const long long i = index++;
    if (!wanted.empty() && !wanted.count(i)) continue;
    const OGRGeometry* g = feature->GetGeometryRef();
    if (!g || g->IsEmpty()) {
      out.notes.push_back("feature " + std::to_string(i) + " has no geometry: skipped");
      continue;
    }
    geometries.emplace_back(i, GeometryPtr(g->clone()));
  }
  for (long long f : wanted)
    if (f >= index)
      throw ModelError(path + ": --feature " + std::to_string(f) + ": the layer has " + std::to_string(index) +
                       " feature" + (index == 1 ? "" : "s") + (options.where ? " matching --where" : ""));
  if (geometries.empty())
    throw ModelError(path + ": no polygon features selected" + (options.where ? " (--where matched none)" : ""));

  for (auto& [i, g] : geometries) {
    if (g->hasCurveGeometry()) g.reset(g->getLinearGeometry());
    polygons_of(g.get(), path + ": feature " + std::to_string(i));  // type check before anything else
  }
  out.crs = project_to_plane(path, layer->GetSpatialRef(), options.crs, geometries, out.warnings, out.crs_wkt);

  // Repair in the plane where the field is built: straight edges between
  // projected vertices are not the images of the edges in longitude and
  // latitude, so data valid there may cross here, and the reverse.
  for (auto& [i, g] : geometries) {
    const std::string where = path + ": feature " + std::to_string(i);
    if (options.repair && !g->IsValid()) {
      if (!OGRGeometryFactory::haveGEOS()) throw ModelError(where + ": --repair needs GDAL built with GEOS");
      GeometryPtr fixed(g->MakeValid());
      if (!fixed || !fixed->IsValid())
        throw ModelError(where + ": GEOS MakeValid could not make it valid (" + QuietGdal::last_message() +
                         "): leave the feature out (--feature, --where) or fix it in a GIS editor");
      out.notes.push_back("feature " + std::to_string(i) +
                          " was invalid and was repaired in the projected plane (GEOS MakeValid)");
      g = std::move(fixed);
    }
  }

  // Several features: dissolve them into one geometry, so that shared
  // borders (adjacent counties) disappear instead of overlapping.
  if (geometries.size() > 1) {
    if (!OGRGeometryFactory::haveGEOS()) throw ModelError(path + ": uniting several features needs GEOS");
    OGRMultiPolygon all;  // UnionCascaded wants the polygons as one multipolygon
    for (auto& [i, g] : geometries)
      for (const OGRPolygon* p : polygons_of(g.get(), path + ": feature " + std::to_string(i))) all.addGeometry(p);
    GeometryPtr united(all.UnionCascaded());
    if (!united) throw ModelError(path + ": the selected features could not be united: " + QuietGdal::last_message());
    out.notes.push_back("united " + std::to_string(geometries.size()) + " features (GEOS union)");
    const long long first = geometries.front().first;
    geometries.clear();
    geometries.emplace_back(first, std::move(united));
  }

  for (auto& [i, g] : geometries) {
    int p = 0;
    for (const OGRPolygon* poly : polygons_of(g.get(), path + ": feature " + std::to_string(i))) {
      PolygonWithHoles pw;
      if (!poly->getExteriorRing()) continue;
      pw.outer = ring_of(poly->getExteriorRing(), i, p, 0);
      for (int h = 0; h < poly->getNumInteriorRings(); ++h)
        pw.holes.push_back(ring_of(poly->getInteriorRing(h), i, p, h + 1));
      out.polygons.polygons.push_back(std::move(pw));
      ++p;
    }
  }
  return out;
}

}  // namespace sage::geometry
