# SPDX-License-Identifier: Apache-2.0
# sf_add_module(<module> SOURCES <file>... [PUBLIC_DEPS <target>...] [PRIVATE_DEPS <target>...]
#               [HEADER_EXCLUDE <file name>...])
#
# One library per folder: target sf_<module>, alias SmoothForce::<module>, file
# libsmoothforce_<module>.so.<SOVERSION> (or .a with BUILD_SHARED_LIBS OFF), position-
# independent. Public headers are <folder>/include/smoothforce/<module>/*.h: a module sees
# another module's headers only when it links it, so CMake enforces the layering. Headers
# beside the sources are private; include/smoothforce/<module>/detail/ is in-tree only. Both
# stay out of the install tree, and so do HEADER_EXCLUDE files.
include_guard(GLOBAL)
include(GNUInstallDirs)

function(sf_add_module module)
  cmake_parse_arguments(M "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS;HEADER_EXCLUDE" ${ARGN})
  set(target sf_${module})
  add_library(${target} ${M_SOURCES})
  add_library(SmoothForce::${module} ALIAS ${target})
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
                                              $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_link_libraries(${target} PUBLIC ${M_PUBLIC_DEPS} PRIVATE ${M_PRIVATE_DEPS})
  set_target_properties(${target} PROPERTIES
    EXPORT_NAME ${module}
    OUTPUT_NAME smoothforce_${module}
    VERSION ${PROJECT_VERSION}
    SOVERSION ${SF_SOVERSION}
    POSITION_INDEPENDENT_CODE ON
    INSTALL_RPATH "$ORIGIN")
  set_property(GLOBAL APPEND PROPERTY SF_MODULE_TARGETS ${target})
  if(SF_INSTALL)
    set(excludes PATTERN detail EXCLUDE)
    foreach(h IN LISTS M_HEADER_EXCLUDE)
      list(APPEND excludes PATTERN ${h} EXCLUDE)
    endforeach()
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
            COMPONENT SmoothForce_Development FILES_MATCHING PATTERN "*.h" ${excludes})
  endif()
endfunction()
