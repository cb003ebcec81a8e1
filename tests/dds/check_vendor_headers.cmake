# Fails when a Fast DDS or Fast CDR header is reachable from a header a
# vendor includes. Runs the compiler's preprocessor with -H (one line per
# header opened, dots for the nesting depth) on a one-line translation unit
# per header, with the include directories given (those a target linking
# mtc::dds gets; for tests/qos, mtc::qos's own).
#
#   cmake -DCXX=<compiler> -DINCLUDES_FILE=<file> -DWORK_DIR=<dir>
#         -DHEADERS=<a;b;...> -P check_vendor_headers.cmake
# INCLUDES_FILE holds one include directory per line.
foreach(var CXX INCLUDES_FILE WORK_DIR HEADERS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_vendor_headers.cmake: ${var} is not set")
  endif()
endforeach()

file(STRINGS "${INCLUDES_FILE}" include_dirs)
set(include_flags "")
foreach(dir IN LISTS include_dirs)
  if(NOT dir STREQUAL "")
    list(APPEND include_flags "-I${dir}")
  endif()
endforeach()
file(MAKE_DIRECTORY "${WORK_DIR}")

set(failed "")
foreach(header IN LISTS HEADERS)
  string(MAKE_C_IDENTIFIER "${header}" stem)
  set(tu "${WORK_DIR}/${stem}.cpp")
  file(WRITE "${tu}" "#include <${header}>\n")
  execute_process(
    COMMAND "${CXX}" -std=c++17 -H -E -o /dev/null ${include_flags} "${tu}"
    RESULT_VARIABLE rc
    OUTPUT_VARIABLE out
    ERROR_VARIABLE tree)
  if(NOT rc EQUAL 0)
    message(SEND_ERROR "<${header}> does not preprocess on its own:\n${tree}")
    list(APPEND failed "${header}")
    continue()
  endif()
  # Walk the include tree ("<dots> <path>" lines); `stack` holds the line
  # that opened each depth, so it is the chain that leads to an offender.
  string(REPLACE "\n" ";" lines "${tree}")
  set(stack "")
  set(count 0)
  set(offender "")
  foreach(line IN LISTS lines)
    if(NOT line MATCHES "^(\\.+) ")
      continue()
    endif()
    math(EXPR count "${count} + 1")
    string(LENGTH "${CMAKE_MATCH_1}" depth)
    math(EXPR keep "${depth} - 1")
    list(SUBLIST stack 0 ${keep} stack)
    list(APPEND stack "${line}")
    if(line MATCHES "/(fastdds|fastrtps|fastcdr)/")
      set(offender "${line}")
      break()
    endif()
  endforeach()
  if(offender)
    list(JOIN stack "\n" chain)
    message(SEND_ERROR "<${header}> reaches a Fast DDS header through:\n${chain}")
    list(APPEND failed "${header}")
  else()
    message(STATUS "<${header}>: ${count} headers, none of Fast DDS or Fast CDR")
  endif()
endforeach()

if(failed)
  message(FATAL_ERROR "Fast DDS reachable from: ${failed}")
endif()
