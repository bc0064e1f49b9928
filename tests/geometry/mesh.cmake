# Tests of the mesh part of sage_geometry (added to geometry_tests).
