# Warnings for sage's own targets (not for consumers).
function(sage_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wno-unknown-pragmas)
endfunction()
