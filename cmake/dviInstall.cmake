# SPDX-License-Identifier: Apache-2.0
# Install rules: headers, the library, find_package(dvi) (giving dvi::dvi)
# and pkg-config's dvi.pc beside the CMake package.
install(TARGETS dvi_library dvi_ensemble EXPORT dviTargets)
include(CMakePackageConfigHelpers)
install(DIRECTORY include/dvi ${PROJECT_BINARY_DIR}/include/dvi
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT dviTargets NAMESPACE dvi:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dvi)
configure_package_config_file(cmake/dviConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/dviConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dvi)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/dviConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/dviConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/dviConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/dvi)

# pkg-config: libdvi is static by default, so its SUNDIALS and KLU
# dependencies are part of Libs (Libs.private when built shared).
get_target_property(DVI_LIBRARY_TYPE dvi_library TYPE)
set(DVI_PC_DEPENDENCIES "-lsundials_cvode -lsundials_ida -lsundials_sunlinsolklu \
-lsundials_sunmatrixsparse -lsundials_nvecserial -lklu")
if(DVI_LIBRARY_TYPE STREQUAL "STATIC_LIBRARY")
  set(DVI_PC_LIBS "${DVI_PC_DEPENDENCIES}")
  set(DVI_PC_LIBS_PRIVATE "")
else()
  set(DVI_PC_LIBS "")
  set(DVI_PC_LIBS_PRIVATE "${DVI_PC_DEPENDENCIES}")
endif()
# Relocatable: the prefix is found from the .pc file's own place, so that
# `cmake --install --prefix` anywhere gives a working dvi.pc.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(DVI_PC_PREFIX "${CMAKE_INSTALL_PREFIX}")
else()
  file(RELATIVE_PATH DVI_PC_UP "/root/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/root")
  set(DVI_PC_PREFIX "\${pcfiledir}/${DVI_PC_UP}")
endif()
configure_file(cmake/dvi.pc.in ${CMAKE_CURRENT_BINARY_DIR}/dvi.pc @ONLY)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/dvi.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
