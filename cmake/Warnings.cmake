# Warnings are errors for our own code; third-party headers come in as SYSTEM includes.
function(marionette_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Werror
    -Wshadow -Wnon-virtual-dtor -Wcast-align -Wunused -Woverloaded-virtual)
endfunction()
