# Warnings are errors for our own code; third-party headers come in as SYSTEM includes.
function(marionette_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Werror
    -Wshadow -Wnon-virtual-dtor -Wcast-align -Wunused -Woverloaded-virtual
    # GCC 12 reports a false -Wrestrict inside std::string's operator+ at -O2/-O3
    # (GCC bug 105651); nothing in our code can cause it.
    $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)
endfunction()
