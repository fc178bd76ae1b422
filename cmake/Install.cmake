# `cmake --install build --prefix P`: the program, the module libraries and their headers, and a CMake package
# (find_package(marchcheck CONFIG REQUIRED); targets marchcheck::files, ::meshes, ::sdf, ::gpu, ::march, ::validation,
# ::reports, ::commands and the program marchcheck::marchcheck). The libraries' private dependencies stay inside them, so a
# user's project needs GLM, and GoogleTest for the test helpers.
include(CMakePackageConfigHelpers)

get_property(marchcheck_modules GLOBAL PROPERTY MARCHCHECK_MODULES)
install(TARGETS ${marchcheck_modules} marchcheck EXPORT marchcheckTargets
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
set(marchcheck_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/marchcheck)
install(EXPORT marchcheckTargets NAMESPACE marchcheck:: DESTINATION ${marchcheck_cmake_dir})
configure_package_config_file(cmake/marchcheckConfig.cmake.in marchcheckConfig.cmake
                              INSTALL_DESTINATION ${marchcheck_cmake_dir})
# 0.x: a minor version may change the interface.
write_basic_package_version_file(marchcheckConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/marchcheckConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/marchcheckConfigVersion.cmake
        DESTINATION ${marchcheck_cmake_dir})

# A Debian package of the same files under /usr (scripts/package.sh builds a portable one and installs it): the
# Debian packages its libraries load come from dpkg-shlibdeps; GLM for the CMake package's find_dependency; EGL and
# OpenGL, which libepoxy loads on first use (dpkg-shlibdeps cannot see them).
set(CPACK_PACKAGE_NAME marchcheck)
set(CPACK_PACKAGE_VENDOR marchcheck)
set(CPACK_PACKAGE_CONTACT "marchcheck developers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "Numerical validation of signed-distance-field ray marching")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${CMAKE_BINARY_DIR}/sdf ${CMAKE_BINARY_DIR}/gpu ${CMAKE_BINARY_DIR}/meshes
    ${CMAKE_BINARY_DIR}/march ${CMAKE_BINARY_DIR}/validation ${CMAKE_BINARY_DIR}/reports ${CMAKE_BINARY_DIR}/commands
    ${CMAKE_BINARY_DIR}/files)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libglm-dev, libegl1, libopengl0")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3-matplotlib, libgtest-dev")
include(CPack)
