# `cmake --install`: the core library and its headers, and (unless REFRASTER_CORE_ONLY) the
# harness libraries and headers, the CLI and the GL workers; a CMake package exporting
# refraster::refraster and refraster::harness, and a pkg-config file for the core
# (docs/library.md).
include(CMakePackageConfigHelpers)

set(REFRASTER_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/refraster)
# The GL workers are programs the harness starts, not commands: libexec, where the harness looks
# for them beside an installed bin/ (harness/src/backends/backend_gl.cpp, gl_worker_path).
set(REFRASTER_INSTALL_WORKERDIR ${CMAKE_INSTALL_LIBEXECDIR}/refraster)

install(TARGETS refraster EXPORT refrasterCoreTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/refraster/include/refraster
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT refrasterCoreTargets NAMESPACE refraster::
  DESTINATION ${REFRASTER_INSTALL_CMAKEDIR})

if(NOT REFRASTER_CORE_ONLY)
  install(TARGETS harness_core harness_image_io refraster_harness EXPORT refrasterHarnessTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/harness/include/harness
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT refrasterHarnessTargets NAMESPACE refraster::
    DESTINATION ${REFRASTER_INSTALL_CMAKEDIR})
  install(TARGETS refraster_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  # The image codec module image_io.cpp loads for EXR, GIF and other files: lib/refraster,
  # found from bin/ or from the configured prefix (harness/CMakeLists.txt).
  install(TARGETS harness_oiio_codec LIBRARY DESTINATION ${REFRASTER_CODEC_INSTALL_DIR})
  foreach(_worker refraster-worker-osmesa refraster-worker-egl)
    if(TARGET ${_worker})
      install(TARGETS ${_worker} RUNTIME DESTINATION ${REFRASTER_INSTALL_WORKERDIR})
    endif()
  endforeach()
endif()

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/refrasterConfig.cmake.in
  ${PROJECT_BINARY_DIR}/package/refrasterConfig.cmake
  INSTALL_DESTINATION ${REFRASTER_INSTALL_CMAKEDIR}
  PATH_VARS REFRASTER_INSTALL_WORKERDIR)
# 0.x: a minor version may change the interface.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/refrasterConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/package/refrasterConfig.cmake
  ${PROJECT_BINARY_DIR}/package/refrasterConfigVersion.cmake
  DESTINATION ${REFRASTER_INSTALL_CMAKEDIR})

# pkg-config, the core only; its prefix is found from the file's own place, so that an
# installation moved or made with `cmake --install --prefix` stays right.
file(RELATIVE_PATH REFRASTER_PC_TO_PREFIX "/prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/prefix")
configure_file(${PROJECT_SOURCE_DIR}/cmake/refraster.pc.in ${PROJECT_BINARY_DIR}/package/refraster.pc
  @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/package/refraster.pc
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
