# `cmake --install build --prefix P`: the program, the module libraries and their headers, and a CMake package
# (find_package(marchcheck CONFIG REQUIRED); targets marchcheck::sdf, ::meshes, ::march, ::validation,
# ::reports and the program marchcheck::marchcheck). The libraries' private dependencies stay inside them, so a
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
