# Sources of the mesh (polyhedral B-rep) part of sage_geometry.
target_sources(sage_geometry PRIVATE
  src/mesh_model.cpp
  src/mesh_reader.cpp
  src/off_reader.cpp
  src/ply_reader.cpp
  src/mesh_validation.cpp
  src/mesh_classifier.cpp
  src/mesh_field.cpp
  src/mesh_csg.cpp
  src/mesh_deficiency.cpp
  src/mesh_shells.cpp)
