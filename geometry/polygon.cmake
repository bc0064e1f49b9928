# Sources of the polygon (GIS) part of sage_geometry.
target_sources(sage_geometry PRIVATE
  src/gis_model.cpp
  src/gis_reader.cpp
  src/polygon.cpp
  src/polygon_brep.cpp
  src/polygon_csg.cpp
  src/polygon_validation.cpp
  src/well_formedness.cpp)
