# Tests of the polygon (GIS) part of sage_geometry (added to geometry_tests).
