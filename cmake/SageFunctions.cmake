# Helpers for sage's own targets. sage_warnings: warnings (not for consumers).
function(sage_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wno-unknown-pragmas)
endfunction()

# sage_library(NAME SOURCES...): a library sage_NAME with the alias
# sage::NAME, its public headers under NAME's include/ folder, and sage's
# warnings. Callers add their own dependencies.
function(sage_library name)
  add_library(sage_${name} ${ARGN})
  add_library(sage::${name} ALIAS sage_${name})
  set_target_properties(sage_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(sage_${name} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  sage_warnings(sage_${name})
endfunction()
