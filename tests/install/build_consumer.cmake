# Configures, builds and runs tests/install/consumer for one component
# against the installed prefix, with the packages it must not need
# disabled. Fails (with the tool's output) at the first step that does.
#   cmake -DCOMPONENT=dds "-DMUST_NOT_NEED=pugixml;Boost" -DPREFIX=<prefix>
#         -DPACKAGE_DIR=<prefix>/lib/cmake/mtconnect-dds
#         -DSOURCE_DIR=<consumer> -DWORK_DIR=<build> -DCXX=<compiler>
#         [-DCXX_FLAGS=<flags of a sanitizer build, compile and link>]
#         -P build_consumer.cmake
foreach(var COMPONENT PREFIX PACKAGE_DIR SOURCE_DIR WORK_DIR CXX)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "build_consumer.cmake: -D${var}=... is required")
  endif()
endforeach()

function(run step)
  execute_process(COMMAND ${ARGN}
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "mtc::${COMPONENT} consumer: ${step} failed (${rc}):\n${out}")
  endif()
  message(STATUS "mtc::${COMPONENT} consumer: ${step} ok\n${out}")
endfunction()

set(disabled "")
foreach(package IN LISTS MUST_NOT_NEED)
  list(APPEND disabled -DCMAKE_DISABLE_FIND_PACKAGE_${package}=ON)
endforeach()

file(REMOVE_RECURSE ${WORK_DIR})
# The package is looked up in the prefix only: no package registry, and
# mtconnect-dds_DIR points into the prefix.
run(configure ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}
  -DCMAKE_CXX_COMPILER=${CXX}
  "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}"
  "-DCMAKE_EXE_LINKER_FLAGS=${CXX_FLAGS}"
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
  -DCMAKE_PREFIX_PATH=${PREFIX}
  -Dmtconnect-dds_DIR=${PACKAGE_DIR}
  -DMTC_COMPONENT=${COMPONENT}
  ${disabled})
run(build ${CMAKE_COMMAND} --build ${WORK_DIR})
run(run ${WORK_DIR}/consumer)
