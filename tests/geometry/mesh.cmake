# Tests of the mesh part of sage_geometry (added to geometry_tests).
target_sources(geometry_tests PRIVATE
  mesh_orientation_test.cpp
  mesh_test.cpp)

# The readers' test replaces the global operator new to watch allocations:
# a program of its own, so that the libraries the other tests load (PROJ's
# nothrow and aligned news, freed through the replaced delete) keep their
# allocator pairs under AddressSanitizer.
sage_add_test(mesh_reader_tests
  SOURCES mesh_reader_test.cpp
  LIBS sage_geometry CGAL::CGAL)
