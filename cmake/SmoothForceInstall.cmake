# SPDX-License-Identifier: Apache-2.0
# Install rules: the libraries (SmoothForce::<module>, ::core, ::runtime), the public include
# trees (sf_add_module), the CMake package (SmoothForceConfig.cmake, its version file,
# SmoothForceTargets.cmake) and smoothforce.pc for pkg-config. sf_kernels is build-only.
include(CMakePackageConfigHelpers)

get_property(sf_targets GLOBAL PROPERTY SF_MODULE_TARGETS)
install(TARGETS ${sf_targets} EXPORT SmoothForceTargets
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT SmoothForce_Runtime
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT SmoothForce_Runtime
                NAMELINK_COMPONENT SmoothForce_Development
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT SmoothForce_Development)

set(SF_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/SmoothForce)
install(EXPORT SmoothForceTargets NAMESPACE SmoothForce:: DESTINATION ${SF_CMAKE_DIR}
        COMPONENT SmoothForce_Development)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/SmoothForceConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/SmoothForceConfig.cmake INSTALL_DESTINATION ${SF_CMAKE_DIR})
# 0.x: only the same minor version is compatible (see SF_SOVERSION).
write_basic_package_version_file(${PROJECT_BINARY_DIR}/SmoothForceConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/SmoothForceConfig.cmake ${PROJECT_BINARY_DIR}/SmoothForceConfigVersion.cmake
        DESTINATION ${SF_CMAKE_DIR} COMPONENT SmoothForce_Development)

# pkg-config: core + runtime (sweep is CMake only). Libraries in link order, top first.
set(SF_PC_LIBS "")
foreach(m runtime force opencl query patch mesh base)
  string(APPEND SF_PC_LIBS " -lsmoothforce_${m}")
endforeach()
string(STRIP "${SF_PC_LIBS}" SF_PC_LIBS)
set(SF_PC_REQUIRES_PRIVATE "tbb libxxhash libhwy")
set(SF_PC_LIBS_PRIVATE "-lembree3 -losdCPU -pthread")
if(SF_OPENCL)
  string(APPEND SF_PC_REQUIRES_PRIVATE " OpenCL")
endif()
# Relocatable: prefix relative to the .pc file's own folder (pkg-config's ${pcfiledir}).
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}" OR IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(SF_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()
  file(RELATIVE_PATH sf_up /p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /p)
  string(REGEX REPLACE "/$" "" sf_up "${sf_up}")
  set(SF_PC_PREFIX "\${pcfiledir}/${sf_up}")
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/smoothforce.pc.in ${PROJECT_BINARY_DIR}/smoothforce.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/smoothforce.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig
        COMPONENT SmoothForce_Development)
# The licence and the changelog, where Debian-style installs keep a package's documents.
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/CHANGELOG.md DESTINATION ${CMAKE_INSTALL_DOCDIR}
        COMPONENT SmoothForce_Development)
