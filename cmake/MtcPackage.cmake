# The installed package, one component per library target, so that a vendor
# looks up only what the targets it asks for need:
#   find_package(mtconnect-dds REQUIRED COMPONENTS dds)   # Fast DDS, Threads
#   target_link_libraries(app PRIVATE mtc::dds)
# finds neither pugixml nor Boost (those belong to the bridge components).
# Without COMPONENTS every component of the installation is loaded.
#
# mtc_export_component(<target> <component>)
#   installs <target> with its own export file
#   (mtconnect-dds-<component>-targets.cmake) and registers it.
# mtc_install_package_config()
#   call once at the end of the top-level CMakeLists.txt, after every
#   target_link_libraries(): reads each component's link libraries and
#   writes mtconnect-ddsConfig.cmake with, per component, the components it
#   needs and a find_dependency() for every package behind them. A link
#   library that is neither an mtc component nor a package listed below is a
#   configure error, so a new dependency cannot be forgotten in the config.

set(MTC_PACKAGE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/mtconnect-dds)

# Imported target -> the find_package() arguments that provide it (the
# versions the project itself asks for).
set(_mtc_package_of_fastrtps "fastrtps 2.9")
set(_mtc_package_of_fastcdr "fastcdr")
set(_mtc_package_of_Threads::Threads "Threads")
set(_mtc_package_of_pugixml::pugixml "pugixml")
set(_mtc_package_of_Boost::headers "Boost 1.74")
set(_mtc_package_of_OpenSSL::Crypto "OpenSSL")
set(_mtc_package_of_OpenSSL::SSL "OpenSSL")
set(_mtc_package_of_CycloneDDS::ddsc "CycloneDDS 0.10")

function(mtc_export_component target component)
  install(TARGETS ${target} EXPORT mtconnect-dds-${component}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(EXPORT mtconnect-dds-${component}
    NAMESPACE mtc::
    FILE mtconnect-dds-${component}-targets.cmake
    DESTINATION ${MTC_PACKAGE_DIR})
  set_property(GLOBAL APPEND PROPERTY MTC_COMPONENTS ${component})
  set_property(GLOBAL PROPERTY MTC_COMPONENT_TARGET_${component} ${target})
endfunction()

# The mtc components and packages `component`'s target links directly.
# Static libraries carry their private links too (as $<LINK_ONLY:...>): a
# consumer links those as well, so they count.
function(_mtc_direct_needs component components_var packages_var)
  get_property(target GLOBAL PROPERTY MTC_COMPONENT_TARGET_${component})
  get_target_property(links ${target} INTERFACE_LINK_LIBRARIES)
  set(components "")
  set(packages "")
  foreach(link IN LISTS links)
    string(REGEX REPLACE "^\\$<LINK_ONLY:(.+)>$" "\\1" link "${link}")
    if(link MATCHES "^mtc::(.+)$")
      list(APPEND components ${CMAKE_MATCH_1})
    elseif(DEFINED _mtc_package_of_${link})
      list(APPEND packages "${_mtc_package_of_${link}}")
    elseif(link)
      message(FATAL_ERROR "mtc::${component} links '${link}': add the package providing it "
                          "to cmake/MtcPackage.cmake so the package config finds it")
    endif()
  endforeach()
  set(${components_var} "${components}" PARENT_SCOPE)
  set(${packages_var} "${packages}" PARENT_SCOPE)
endfunction()

function(mtc_install_package_config)
  get_property(all GLOBAL PROPERTY MTC_COMPONENTS)
  set(table "set(_mtc_all_components ${all})\n")
  foreach(component IN LISTS all)
    # Transitive closure; components are registered after what they link,
    # which the config relies on to load them in order.
    set(needs "")
    set(packages "")
    set(todo ${component})
    while(todo)
      list(POP_FRONT todo current)
      _mtc_direct_needs(${current} direct_components direct_packages)
      list(APPEND packages ${direct_packages})
      foreach(dep IN LISTS direct_components)
        if(NOT dep IN_LIST all)
          message(FATAL_ERROR "mtc::${current} links mtc::${dep}, which is not exported")
        endif()
        list(FIND all ${dep} dep_index)
        list(FIND all ${component} own_index)
        if(dep_index GREATER own_index)
          message(FATAL_ERROR "mtc::${dep} must be exported before mtc::${component}")
        endif()
        if(NOT dep IN_LIST needs)
          list(APPEND needs ${dep})
          list(APPEND todo ${dep})
        endif()
      endforeach()
    endwhile()
    list(REMOVE_DUPLICATES packages)
    string(APPEND table "set(_mtc_${component}_needs ${needs})\n")
    string(APPEND table "set(_mtc_${component}_packages")
    foreach(package IN LISTS packages)
      string(APPEND table " \"${package}\"")
    endforeach()
    string(APPEND table ")\n")
  endforeach()
  set(MTC_COMPONENT_TABLE "${table}")
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/mtconnect-ddsConfig.cmake.in
    ${PROJECT_BINARY_DIR}/mtconnect-ddsConfig.cmake
    INSTALL_DESTINATION ${MTC_PACKAGE_DIR})
  write_basic_package_version_file(
    ${PROJECT_BINARY_DIR}/mtconnect-ddsConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
  install(FILES
    ${PROJECT_BINARY_DIR}/mtconnect-ddsConfig.cmake
    ${PROJECT_BINARY_DIR}/mtconnect-ddsConfigVersion.cmake
    DESTINATION ${MTC_PACKAGE_DIR})
endfunction()
