# Tests of the polygon (GIS) part of sage_geometry (added to geometry_tests).
target_sources(geometry_tests PRIVATE
  gis_test.cpp
  polygon_field_test.cpp)
target_link_libraries(geometry_tests PRIVATE GDAL::GDAL)  # CRS checks with OGRSpatialReference
