# Warnings every project target builds with. Clean under -Wall -Wextra is a
# requirement, so CI can add -Werror (MTC_WERROR=ON) without surprises.
option(MTC_WERROR "Treat warnings as errors" OFF)

function(mtc_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
    -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Woverloaded-virtual
    -Wnull-dereference -Wimplicit-fallthrough)
  if(MTC_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
