#pragma once
// GIS polygons (GeoJSON, Shapefile, GeoPackage and whatever else GDAL/OGR
// reads) to fields: validation with CGAL's exact predicates, projection of
// longitude/latitude to a local metric system, well-formed CSG by the
// decreasing convex hull, or trimmed-edge B-rep fields.

#include <sage/geometry/model.hpp>

#include <string>

namespace sage::geometry {

/// Reads the selected features' polygons and builds their field. Throws
/// ModelError naming the file, feature, ring and vertex of any fault.
Model load_gis(const std::string& path, const LoadOptions& options);

/// True for extensions that are GIS vector data (.geojson, .shp, .gpkg,
/// ...), and for .json files whose content is GeoJSON.
bool is_gis_path(const std::string& path);

}  // namespace sage::geometry
