# Sources of the CAD part of sage_geometry: STEP, IGES and BREP solids
# through OpenCASCADE (Debian's libocct-*-dev 7.6), or a stub that refuses
# CAD files with -DSAGE_WITH_CAD=OFF.
target_sources(sage_geometry PRIVATE src/cad_faces.cpp)
if(SAGE_WITH_CAD)
  target_sources(sage_geometry PRIVATE
    src/cad_csg.cpp
    src/cad_literals.cpp
    src/cad_model.cpp
    src/cad_reader.cpp
    src/cad_samples.cpp
    src/cad_surfaces.cpp
    src/sign_cover.cpp)
  # OCCT 7.6's targets carry no include directories.
  target_include_directories(sage_geometry SYSTEM PRIVATE ${OpenCASCADE_INCLUDE_DIR})
  target_link_libraries(sage_geometry PRIVATE ${SAGE_OCCT_LIBRARIES})
else()
  target_sources(sage_geometry PRIVATE src/cad_unavailable.cpp)
endif()
