# `cmake --install`: headers (with caustix.glsl), the libraries an
# application links, caustix-bake / caustix-render / caustix-inspect, the
# CMake package (find_package(caustix): caustix::formats, caustix::runtime,
# caustix::caustix-bake and caustix_bake()) and a pkg-config file.
# docs/embedding.md ("Installing") is the user's side of it.
include(CMakePackageConfigHelpers)
set(CAUSTIX_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/caustix)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/common/include/ ${PROJECT_SOURCE_DIR}/formats/include/
                  ${PROJECT_SOURCE_DIR}/runtime/include/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT development)
install(FILES ${PROJECT_BINARY_DIR}/common/include/caustix/common/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/caustix/common COMPONENT development)

install(TARGETS caustix_common caustix_formats caustix_formats_draco caustix_scene_loader caustix_gl caustix_runtime
        EXPORT caustixTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS caustix-bake EXPORT caustixTargets RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS caustix-render caustix-inspect RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT caustixTargets NAMESPACE caustix:: DESTINATION ${CAUSTIX_CMAKE_DIR} COMPONENT development)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/caustixConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/caustixConfig.cmake
                              INSTALL_DESTINATION ${CAUSTIX_CMAKE_DIR}
                              PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
# Versioning (docs/embedding.md): a package of another major version is not
# compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/caustixConfigVersion.cmake
                                 COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/caustixConfig.cmake ${PROJECT_BINARY_DIR}/caustixConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/caustixBake.cmake
        DESTINATION ${CAUSTIX_CMAKE_DIR} COMPONENT development)

file(RELATIVE_PATH CAUSTIX_PC_TO_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
configure_file(${PROJECT_SOURCE_DIR}/cmake/caustix.pc.in ${PROJECT_BINARY_DIR}/caustix.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/caustix.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT development)
