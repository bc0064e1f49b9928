# Tests of the mesh part of sage_geometry (added to geometry_tests).
target_sources(geometry_tests PRIVATE
  mesh_orientation_test.cpp
  mesh_reader_test.cpp
  mesh_test.cpp)
