#pragma once
// Point layers for `sage sample`: places read from a CSV file (columns x,
// y and z, or lon and lat, ...) or any OGR point layer (GeoPackage,
// GeoJSON, Shapefile, ...), brought into the plane a model's field is
// built in, and written back, feature by feature, with their attributes
// and the samples as new ones, in the format the output's extension names.
//
// Coordinates follow the polygons' rules (gis_reader.cpp): the points'
// CRS is --points-crs when given, else the layer's; points with a CRS are
// transformed into the model's plane (for longitude/latitude polygons, the
// local projection sage chose for them); points without one are taken as
// coordinates of that plane, with a warning when they could be degrees.

#include <sage/sampling/point_array.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace sage::output {

struct PointLayerOptions {
  std::optional<std::string> layer;  // by name (default: the first)
  std::optional<std::string> crs;    // the points' CRS, in place of the file's: EPSG:4326, a PROJ string, WKT
};

struct PointLayer {
  std::vector<std::array<double, 3>> points;  // in the model's plane; z = 0 where the points have none
  bool has_z = false;                         // every point has a z
  std::string coordinates;                    // how they were read, in words
  std::vector<std::string> warnings;
};

/// The file formats write_point_layer knows, for messages: ".csv, .geojson, ...".
std::string point_layer_formats();

/// Reads the points of `path`'s layer. `plane_wkt`: the coordinate
/// reference system of the model's plane (empty: none; then the points are
/// used as they are). Throws OutputError naming the file and the feature:
/// no such file or layer, a feature that is not a point, a CRS that PROJ
/// does not know.
PointLayer read_point_layer(const std::string& path, const std::string& plane_wkt, const PointLayerOptions& options);

/// Writes `input`'s features in order, each with its geometry (as in the
/// input) and attributes, and one Real attribute per array (components 1,
/// one value per point). The format follows `output`'s extension; a CSV
/// from a layer that is not CSV gets the geometry as X, Y (and Z) columns.
void write_point_layer(const std::string& input, const PointLayerOptions& options, const std::string& output,
                       const std::vector<PointArray>& arrays);

}  // namespace sage::output
