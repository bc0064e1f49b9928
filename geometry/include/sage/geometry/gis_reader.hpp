#pragma once
// Reading polygons from GIS vector data with GDAL/OGR, projected to a
// planar metric system when the data is longitude/latitude.
//
// Projection: geographic data (lon/lat on any datum) is transformed with
// OGR/PROJ to an azimuthal equidistant projection centred on the centre of
// the selected features' bounding box (metres, WGS84 ellipsoid): distances
// from the centre are exact and distortion stays small over a region the
// size of a state. Projected data is used as is; data without a coordinate
// system is assumed planar (with a warning when every coordinate could be
// longitude/latitude), unless LoadOptions::crs names the source system. The
// choice is reported in GisPolygons::crs.
//
// Repair (LoadOptions::repair) happens after projection, in the plane where
// the field is built: a straight edge between projected vertices is not the
// image of the edge in longitude/latitude, so rings that merely touch there
// may cross here.

#include <sage/geometry/model.hpp>
#include <sage/geometry/polygon.hpp>

#include <string>
#include <vector>

namespace sage::geometry {

struct GisPolygons {
  PolygonSet polygons;
  std::string crs;                    // what coordinate system the polygons are in, and how
  std::string crs_wkt;                // that system as WKT2; empty when the data has none
  std::vector<std::string> notes;     // features used, unions and repairs done
  std::vector<std::string> warnings;  // what the user should check (a missing coordinate system)
};

/// Reads the polygons of the selected features (options.features,
/// options.where, options.layer); several features are united (GEOS).
/// With options.repair, invalid geometry is made valid (GEOS MakeValid) in
/// the projected plane, or refused with the feature named.
/// Throws ModelError naming the file and the feature.
GisPolygons read_gis_polygons(const std::string& path, const LoadOptions& options);

}  // namespace sage::geometry
