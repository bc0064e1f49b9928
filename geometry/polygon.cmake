# Sources of the polygon (GIS) part of sage_geometry.
target_sources(sage_geometry PRIVATE
  src/gis_model.cpp)
