# Sanitizer and fuzzing builds (scripts/test.sh --sanitize asan|tsan).
#   MTC_SANITIZE=address  AddressSanitizer + UndefinedBehaviorSanitizer
#   MTC_SANITIZE=thread   ThreadSanitizer
#   MTC_FUZZ=ON           also the libFuzzer targets of tests/fuzz (clang
#                         only; implies address when MTC_SANITIZE is empty)
# Every target of the tree gets the flags, so the whole suite runs under the
# sanitizer; Fast DDS and the other Debian libraries are not instrumented.
set(MTC_SANITIZE "" CACHE STRING "Sanitizer build: address (ASan+UBSan), thread (TSan) or empty")
set_property(CACHE MTC_SANITIZE PROPERTY STRINGS "" address thread)
option(MTC_FUZZ "Build the libFuzzer targets of tests/fuzz (clang only)" OFF)

if(MTC_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "MTC_FUZZ=ON needs clang (libFuzzer): configure with "
                        "-DCMAKE_CXX_COMPILER=clang++")
  endif()
  if(MTC_SANITIZE STREQUAL "")
    set(MTC_SANITIZE address CACHE STRING "" FORCE)
  elseif(NOT MTC_SANITIZE STREQUAL "address")
    message(FATAL_ERROR "MTC_FUZZ=ON goes with MTC_SANITIZE=address, not '${MTC_SANITIZE}'")
  endif()
endif()

if(MTC_SANITIZE STREQUAL "address")
  # UB aborts the test instead of printing and going on: a report is a failure.
  set(mtc_sanitize_flags -fsanitize=address,undefined -fno-sanitize-recover=all)
elseif(MTC_SANITIZE STREQUAL "thread")
  set(mtc_sanitize_flags -fsanitize=thread)
elseif(NOT MTC_SANITIZE STREQUAL "")
  message(FATAL_ERROR "MTC_SANITIZE must be address, thread or empty, not '${MTC_SANITIZE}'")
endif()

# What a program built outside this tree needs to link these libraries
# (tests/install builds such programs), as one string.
string(JOIN " " MTC_SANITIZE_FLAGS ${mtc_sanitize_flags})
if(mtc_sanitize_flags)
  # -O1 keeps the instrumented suite fast enough for CI and the stacks readable.
  add_compile_options(${mtc_sanitize_flags} -fno-omit-frame-pointer -O1)
  add_link_options(${mtc_sanitize_flags})
endif()
if(MTC_FUZZ)
  # Coverage feedback for libFuzzer from every library a fuzz target links;
  # the ASan runtime provides the hooks to the other executables.
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
