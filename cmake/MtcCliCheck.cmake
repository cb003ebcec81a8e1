# The command-line contract of everything a user runs: every executable the
# project builds (outside tests/) and every tool script answers
#   --help                      usage on stdout, exit 0, within seconds, no run
#   --definitely-not-an-option  a message on stderr, exit 2, no run
# and so does each command an executable's usage lists under "Commands:"
# (`mtc watch`, ...). mtc_add_cli_checks() finds the programs itself, the
# executables by walking the targets of every directory and the scripts by
# glob, so a new one is checked without anyone having to register it.
# Call it once, at the end of the top-level CMakeLists.txt (after every
# add_subdirectory). One CTest test per program, label "cli", each inside
# the loopback-only namespace (scripts/netns-run.sh, a no-op when ctest
# already runs in one).

# Executable targets defined in `dir` and below, tests/ left out (GoogleTest
# binaries have their own command line).
function(_mtc_executables_below dir out_var)
  set(found "")
  get_property(targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(type STREQUAL "EXECUTABLE")
      list(APPEND found ${target})
    endif()
  endforeach()
  set(tests_root "${PROJECT_SOURCE_DIR}/tests")
  get_property(subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    cmake_path(IS_PREFIX tests_root "${sub}" NORMALIZE under_tests)
    if(NOT under_tests)
      _mtc_executables_below("${sub}" below)
      list(APPEND found ${below})
    endif()
  endforeach()
  set(${out_var} "${found}" PARENT_SCOPE)
endfunction()

function(mtc_add_cli_checks)
  set(netns ${PROJECT_SOURCE_DIR}/scripts/netns-run.sh)
  set(check ${PROJECT_SOURCE_DIR}/tests/cli/check_cli.sh)
  set(cli_tests "")

  _mtc_executables_below("${PROJECT_SOURCE_DIR}" executables)
  if(NOT executables)
    message(FATAL_ERROR "mtc_add_cli_checks: found no executable targets to check")
  endif()
  foreach(target IN LISTS executables)
    get_target_property(name ${target} OUTPUT_NAME)
    if(NOT name)
      set(name ${target})
    endif()
    add_test(NAME cli.${name} COMMAND ${netns} ${check} $<TARGET_FILE:${target}>)
    list(APPEND cli_tests cli.${name})
  endforeach()

  # Scripts: shell and Python tools, CTest drivers included.
  file(GLOB_RECURSE scripts CONFIGURE_DEPENDS LIST_DIRECTORIES false
    RELATIVE ${PROJECT_SOURCE_DIR}
    ${PROJECT_SOURCE_DIR}/scripts/*.sh ${PROJECT_SOURCE_DIR}/scripts/*.py
    ${PROJECT_SOURCE_DIR}/apps/*.sh ${PROJECT_SOURCE_DIR}/apps/*.py
    ${PROJECT_SOURCE_DIR}/benchmarks/*.sh ${PROJECT_SOURCE_DIR}/benchmarks/*.py
    ${PROJECT_SOURCE_DIR}/tests/*.sh ${PROJECT_SOURCE_DIR}/tests/*.py
    ${PROJECT_SOURCE_DIR}/examples/*.sh ${PROJECT_SOURCE_DIR}/docs/*.py)
  foreach(script IN LISTS scripts)
    add_test(NAME cli.${script} COMMAND ${netns} ${check} ${PROJECT_SOURCE_DIR}/${script})
    list(APPEND cli_tests cli.${script})
  endforeach()
  # Each run inside has its own limit (check_cli.sh, 30 s); this one only
  # catches the check itself hanging (mtc: ten runs).
  set_tests_properties(${cli_tests} PROPERTIES LABELS "cli" TIMEOUT 400)
endfunction()
