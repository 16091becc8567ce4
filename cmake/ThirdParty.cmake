# Every dependency is a Debian 12 package; scripts/setup-deps.sh installs them.
find_package(glm 0.9.9 CONFIG REQUIRED)
find_package(nlohmann_json 3.11 CONFIG REQUIRED)
# The scene loader's parser (harness/src/scene/strict_json.cpp); Debian's libsimdjson-dev exports
# simdjson::simdjson.
find_package(simdjson 3.0 CONFIG REQUIRED)
if(REFRASTER_FUZZ)
  return()  # the fuzz targets need the core and harness_core only
endif()
find_package(CLI11 2.1 CONFIG REQUIRED)
find_package(OpenImageIO CONFIG REQUIRED)
# Texture files are decoded with libpng alone (harness/src/io/image_io.cpp, read_texture_png).
find_package(PNG REQUIRED)
# Debian 12: the exported OpenImageIO target lists /usr/include/opencv4, which exists only
# with libopencv-dev installed; CMake then refuses to generate. Drop that directory.
get_target_property(_oiio_inc OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
list(FILTER _oiio_inc EXCLUDE REGEX "opencv4")
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_oiio_inc}")

find_package(PkgConfig REQUIRED)
if(NOT REFRASTER_WITH_OSMESA STREQUAL "OFF")
  if(REFRASTER_WITH_OSMESA STREQUAL "ON")
    pkg_check_modules(OSMesa REQUIRED IMPORTED_TARGET osmesa)
  else()
    pkg_check_modules(OSMesa IMPORTED_TARGET osmesa)
  endif()
endif()
if(NOT REFRASTER_WITH_EGL STREQUAL "OFF")
  if(REFRASTER_WITH_EGL STREQUAL "ON")
    find_package(OpenGL REQUIRED COMPONENTS EGL OpenGL)
  else()
    find_package(OpenGL COMPONENTS EGL OpenGL)
  endif()
endif()

if(REFRASTER_BUILD_TESTS)
  find_package(GTest 1.12 CONFIG REQUIRED)
  find_package(benchmark CONFIG)
endif()
