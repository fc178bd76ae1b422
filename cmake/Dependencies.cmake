# Debian 12 packages (scripts/setup.sh installs them); the lines are the ones ../shared/BUILD-NOTES.md verified.
find_package(glm CONFIG REQUIRED)
find_package(nlohmann_json 3.11 CONFIG REQUIRED)
find_package(CLI11 CONFIG REQUIRED)
find_package(fmt 9 CONFIG REQUIRED)
find_package(TBB CONFIG REQUIRED)
find_package(OpenImageIO 2.4 CONFIG REQUIRED)
find_package(PNG REQUIRED)  # the PNGs renders write, without loading OpenImageIO
find_package(ZLIB REQUIRED)  # their rows deflated in pieces on every core
find_package(embree 3 CONFIG REQUIRED)  # target: embree

# OIIO's exported targets name /usr/include/opencv4, which Debian does not ship without libopencv-dev.
foreach(target OpenImageIO::OpenImageIO OpenImageIO::OpenImageIO_Util)
  foreach(property INTERFACE_INCLUDE_DIRECTORIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES)
    get_target_property(dirs ${target} ${property})
    if(dirs)
      list(FILTER dirs EXCLUDE REGEX "opencv4")
      set_target_properties(${target} PROPERTIES ${property} "${dirs}")
    endif()
  endforeach()
endforeach()

if(MARCHCHECK_BUILD_TESTS)
  find_package(GTest CONFIG REQUIRED)
  include(GoogleTest)
endif()
if(MARCHCHECK_BUILD_BENCH)
  find_package(benchmark CONFIG REQUIRED)
endif()
