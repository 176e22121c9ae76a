# Link fix-ups for ROS 2 installed from PyPI wheels (`pip install ros-jazzy-rclpy ...`).
#
# Installed into a Python virtual environment, the wheels turn the venv into a ROS prefix
# (lib/, include/<pkg>/<pkg>/, share/<pkg>/cmake/) with two quirks that matter to compiled
# executables:
#   * the wheels bundle third-party libraries (openssl, tinyxml2, yaml, lttng) in
#     <venv>/lib/python3.X/site-packages/ros_*.libs/, which the libraries' own RPATHs do not
#     reach once installed into <venv>/lib;
#   * some message libraries (*__rosidl_generator_py) that librcl needs reference symbols of
#     libpython without listing it as a dependency.
# Python processes never notice (a .pth hook of the wheels sets LD_LIBRARY_PATH and re-executes
# the interpreter); a C or C++ executable must be linked with the flags below.
#
# On a standard ROS 2 install (/opt/ros/<distro>, a colcon workspace) no ros_*.libs directory
# exists, ROS_PYPI_WHEELS is FALSE and ros_pypi_wheels_fix_executable() does nothing: delete
# this file and its uses in CMakeLists.txt if you never build against the wheels.

# ros_pypi_wheels_setup(<package>): call after the find_package() calls.
# Sets ROS_PYPI_WHEELS (TRUE/FALSE), ROS_PYPI_WHEELS_PREFIX and ROS_PYPI_WHEELS_LIBS_DIRS;
# <package>_DIR of a package found with find_package() tells where the ROS prefix is.
# With the wheels, it also drops paths that do not exist from the imported targets' include
# directories and link libraries, and points libraries named plainly that only the wheels bundle
# (lttng-ust) at the bundled file: some exported targets name paths of the machine that built
# the wheels (*__rosidl_generator_py: /opt/python/cp311-cp311/include/...; Fast DDS, which
# rcl::rcl reaches through rmw_implementation: /usr/lib64/libtinyxml2.so, bundled in
# ros_fastrtps.libs instead), and CMake refuses to build with a missing one.
macro(ros_pypi_wheels_setup package)
  get_filename_component(ROS_PYPI_WHEELS_PREFIX "${${package}_DIR}/../../.." ABSOLUTE)
  file(GLOB ROS_PYPI_WHEELS_LIBS_DIRS LIST_DIRECTORIES true
    "${ROS_PYPI_WHEELS_PREFIX}/lib/python3*/site-packages/ros_*.libs")
  if(ROS_PYPI_WHEELS_LIBS_DIRS)
    set(ROS_PYPI_WHEELS TRUE)
    message(STATUS "ROS 2 from PyPI wheels in ${ROS_PYPI_WHEELS_PREFIX}: "
      "compiled executables get rpaths and libpython")
    _ros_pypi_wheels_drop_missing_paths()
  else()
    set(ROS_PYPI_WHEELS FALSE)
  endif()
endmacro()

function(_ros_pypi_wheels_drop_missing_paths)
  if(CMAKE_VERSION VERSION_LESS 3.21)
    message(FATAL_ERROR "Building against the ROS 2 PyPI wheels needs CMake >= 3.21")
  endif()
  get_directory_property(_targets IMPORTED_TARGETS)
  foreach(_target IN LISTS _targets)
    foreach(_property INTERFACE_INCLUDE_DIRECTORIES INTERFACE_LINK_LIBRARIES)
      get_target_property(_values ${_target} ${_property})
      if(NOT _values)
        continue()
      endif()
      set(_kept)
      foreach(_value IN LISTS _values)
        # keep target names, flags, generator expressions and paths that exist
        if(IS_ABSOLUTE "${_value}" AND NOT EXISTS "${_value}")
          continue()
        endif()
        # a library named plainly that the wheels bundle under a hashed name (tracetools names
        # lttng-ust: ros_tracetools.libs/liblttng-ust-<hash>.so.0.0.0): that file
        if(_value MATCHES "^[A-Za-z0-9_.+-]+$" AND NOT TARGET "${_value}")
          foreach(_dir IN LISTS ROS_PYPI_WHEELS_LIBS_DIRS)
            file(GLOB _bundled "${_dir}/lib${_value}-[0-9a-f]*.so*")
            if(_bundled)
              list(GET _bundled 0 _value)
              break()
            endif()
          endforeach()
        endif()
        list(APPEND _kept "${_value}")
      endforeach()
      if(NOT _kept STREQUAL _values)
        set_target_properties(${_target} PROPERTIES ${_property} "${_kept}")
      endif()
    endforeach()
  endforeach()
endfunction()

# Give an executable target what it needs to link and run against the wheels' libraries,
# without LD_LIBRARY_PATH: rpath-link + rpath to <prefix>/lib and every ros_*.libs directory,
# --allow-shlib-undefined, and libpython of Python3_EXECUTABLE (the interpreter the wheels
# are installed for).
function(ros_pypi_wheels_fix_executable target)
  if(NOT ROS_PYPI_WHEELS)
    return()
  endif()
  if(NOT Python3_EXECUTABLE)
    find_package(Python3 REQUIRED COMPONENTS Interpreter)
  endif()
  execute_process(
    COMMAND "${Python3_EXECUTABLE}" -c
      "import sysconfig as s; print(s.get_config_var('LIBDIR')); print(s.get_config_var('LDLIBRARY'))"
    OUTPUT_VARIABLE _out
    RESULT_VARIABLE _rc
    OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "Could not ask ${Python3_EXECUTABLE} where libpython is")
  endif()
  string(REPLACE "\n" ";" _out "${_out}")
  list(GET _out 0 _python_libdir)
  list(GET _out 1 _python_library)
  if(NOT _python_library MATCHES "\\.so" OR NOT EXISTS "${_python_libdir}/${_python_library}")
    message(FATAL_ERROR
      "${target}: the ROS 2 wheels' libraries need a shared libpython, but "
      "${Python3_EXECUTABLE} has '${_python_libdir}/${_python_library}'. Use a Python built "
      "with --enable-shared (pyenv: PYTHON_CONFIGURE_OPTS=--enable-shared).")
  endif()

  # Prefixes listed before the wheels' come first: an overlay's libraries must win over the
  # wheels' own (`make overlay` relinks librcl to rmw_implementation; DT_RPATH beats LD_LIBRARY_PATH).
  set(_ahead)
  string(REPLACE ":" ";" _env_prefixes "$ENV{CMAKE_PREFIX_PATH}")
  foreach(_prefix IN LISTS CMAKE_PREFIX_PATH _env_prefixes)
    get_filename_component(_prefix "${_prefix}" ABSOLUTE)
    if(_prefix STREQUAL ROS_PYPI_WHEELS_PREFIX)
      break()
    endif()
    if(IS_DIRECTORY "${_prefix}/lib")
      list(APPEND _ahead "${_prefix}/lib")
    endif()
  endforeach()
  set(_dirs ${_ahead} "${ROS_PYPI_WHEELS_PREFIX}/lib" ${ROS_PYPI_WHEELS_LIBS_DIRS})
  foreach(_dir IN LISTS _dirs)
    target_link_options(${target} PRIVATE "LINKER:-rpath-link,${_dir}")
  endforeach()
  target_link_options(${target} PRIVATE
    "LINKER:--allow-shlib-undefined"
    # DT_RPATH (not DT_RUNPATH) so that the directories also serve the libraries' own
    # dependencies: their embedded RPATHs point into the wheels' build trees
    "LINKER:--disable-new-dtags")
  # needed although no symbol of the executable uses it: keep it despite --as-needed
  target_link_libraries(${target} PRIVATE
    "-Wl,--push-state,--no-as-needed" "${_python_libdir}/${_python_library}" "-Wl,--pop-state")
  set_target_properties(${target} PROPERTIES
    BUILD_RPATH "${_dirs};${_python_libdir}"
    INSTALL_RPATH "${_dirs};${_python_libdir}")
endfunction()
