# install(EXPORT …) so that other programs can find_package(geom) and link geom::geom.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

get_property(geom_libraries GLOBAL PROPERTY GEOM_LIBRARIES)
install(TARGETS ${geom_libraries} geom EXPORT geomTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY geom/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/geom
        FILES_MATCHING PATTERN "*.h")
install(EXPORT geomTargets NAMESPACE geom:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/geom)
configure_package_config_file(cmake/geomConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/geomConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/geom)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/geomConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/geomConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/geomConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/geom)
if(GEOM_BUILD_CLI)
  install(TARGETS geom_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
