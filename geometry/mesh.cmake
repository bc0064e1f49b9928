# Sources of the mesh (polyhedral B-rep) part of sage_geometry.
target_sources(sage_geometry PRIVATE
  src/mesh_model.cpp)
