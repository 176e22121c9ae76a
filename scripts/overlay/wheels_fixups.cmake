# Loaded into every package the overlay builds (CMAKE_PROJECT_INCLUDE, scripts/overlay/build.py):
# at the end of the top-level CMakeLists.txt, when every find_package() has run, drop from the
# imported targets the paths of the machine that built the wheels (/opt/python/cp311-cp311/...,
# /usr/lib64/libtinyxml2.so), which CMake would refuse at generate time. The work is the example
# package's (ros_pypi_wheels.cmake); nothing is changed in the venv.
if(NOT COMMAND _ros_pypi_wheels_drop_missing_paths)
  include("${CMAKE_CURRENT_LIST_DIR}/../../examples/rmw_introspect_examples/cmake/ros_pypi_wheels.cmake")
endif()
if(CMAKE_CURRENT_SOURCE_DIR STREQUAL CMAKE_SOURCE_DIR)
  cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" ID rmw_introspect_overlay_fixups
    CALL _ros_pypi_wheels_drop_missing_paths)
endif()
