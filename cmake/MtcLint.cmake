# Format and static-analysis checks as part of the normal suite (label lint),
# so .ci/run -> scripts/test.sh fails on a formatting slip or a clang-tidy
# finding like on any other failing test. Both call scripts/lint.sh, which
# developers run themselves (`scripts/lint.sh --fix`).
#   lint.format  clang-format --dry-run -Werror over every tracked C/C++ file
#   lint.tidy    clang-tidy over every project translation unit of this build
#                (compile_commands.json), warnings as errors
# A missing tool fails the test (scripts/setup-deps.sh installs both).
function(mtc_add_lint_tests)
  if(NOT CMAKE_EXPORT_COMPILE_COMMANDS)
    message(FATAL_ERROR "mtc_add_lint_tests: lint.tidy needs CMAKE_EXPORT_COMPILE_COMMANDS ON")
  endif()
  set(lint ${PROJECT_SOURCE_DIR}/scripts/lint.sh)
  add_test(NAME lint.format COMMAND ${lint} --format)
  add_test(NAME lint.tidy COMMAND ${lint} --tidy --build ${PROJECT_BINARY_DIR} --jobs 2)
  set_tests_properties(lint.format lint.tidy PROPERTIES LABELS "lint")
  # lint.tidy keeps both cores busy for minutes: ctest -j2 runs it alone
  # rather than beside timing-sensitive DDS tests.
  set_tests_properties(lint.tidy PROPERTIES PROCESSORS 2 TIMEOUT 3600)
endfunction()
