# pytest-rmw-introspect for CMake / ament_cmake packages: register interface contract files as
# tests, so that `colcon test` (ctest) runs them and `colcon test-result` shows them.
#
#   find_package(pytest_rmw_introspect REQUIRED)   # installed with the Python package, in
#                                                   # <prefix>/share/pytest_rmw_introspect/cmake
#   if(BUILD_TESTING)
#     rmw_introspect_add_contract_tests(
#       [DIRECTORY contracts]        # where the *.interfaces.yaml files are (default: contracts)
#       [CONTRACTS a.interfaces.yaml ...]   # instead of every *.interfaces.yaml in DIRECTORY
#       [TIMEOUT 120]                # seconds per contract (a test per contract file)
#       [PYTHON /path/to/python]     # the interpreter that has rclpy and pytest-rmw-introspect
#       [PYTEST_ARGS ...])           # more pytest arguments (e.g. --rmw-introspect-fail-on risky)
#   endif()
#
# Each contract is run with `python -m pytest CONTRACT` (the contract file is a test item of
# the pytest plugin: its target is captured on the recording middleware and compared), with a
# JUnit result file under the package's test results, where colcon test-result finds it. The
# package's install prefix is added to AMENT_PREFIX_PATH, so `package:` targets resolve to it.
include_guard(GLOBAL)
set(pytest_rmw_introspect_FOUND TRUE)

function(rmw_introspect_add_contract_tests)
  cmake_parse_arguments(ARG "" "DIRECTORY;TIMEOUT;PYTHON" "CONTRACTS;PYTEST_ARGS" ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "rmw_introspect_add_contract_tests: unknown arguments ${ARG_UNPARSED_ARGUMENTS} "
      "(known: DIRECTORY, CONTRACTS, TIMEOUT, PYTHON, PYTEST_ARGS)")
  endif()
  if(NOT ARG_DIRECTORY)
    set(ARG_DIRECTORY contracts)
  endif()
  get_filename_component(directory "${ARG_DIRECTORY}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  if(NOT IS_DIRECTORY "${directory}")
    message(FATAL_ERROR "rmw_introspect_add_contract_tests: DIRECTORY ${directory} does not exist")
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 120)
  endif()
  set(python "${ARG_PYTHON}")
  if(NOT python AND Python3_EXECUTABLE)
    set(python "${Python3_EXECUTABLE}")
  endif()
  if(NOT python)
    find_package(Python3 REQUIRED COMPONENTS Interpreter)
    set(python "${Python3_EXECUTABLE}")
  endif()
  execute_process(COMMAND "${python}" -c "import pytest_rmw_introspect"
    RESULT_VARIABLE missing OUTPUT_QUIET ERROR_QUIET)
  if(missing)
    message(WARNING "rmw_introspect_add_contract_tests: ${python} cannot import pytest_rmw_introspect; "
      "the contract tests will fail. Pass PYTHON <the interpreter that has it> (or -DPython3_EXECUTABLE).")
  endif()

  if(ARG_CONTRACTS)
    set(contracts "")
    foreach(contract IN LISTS ARG_CONTRACTS)
      get_filename_component(contract "${contract}" ABSOLUTE BASE_DIR "${directory}")
      if(NOT EXISTS "${contract}")
        message(FATAL_ERROR "rmw_introspect_add_contract_tests: contract ${contract} does not exist")
      endif()
      list(APPEND contracts "${contract}")
    endforeach()
  else()
    file(GLOB contracts CONFIGURE_DEPENDS "${directory}/*.interfaces.yaml")
    list(SORT contracts)
    if(NOT contracts)
      message(WARNING "rmw_introspect_add_contract_tests: no *.interfaces.yaml in ${directory}")
      return()
    endif()
  endif()

  if(DEFINED AMENT_TEST_RESULTS_DIR)
    set(results "${AMENT_TEST_RESULTS_DIR}/${PROJECT_NAME}")
  else()
    set(results "${CMAKE_BINARY_DIR}/test_results/${PROJECT_NAME}")
  endif()
  foreach(contract IN LISTS contracts)
    get_filename_component(file_name "${contract}" NAME)
    string(REGEX REPLACE "\\.(interfaces|system)\\.ya?ml$" "" stem "${file_name}")
    string(MAKE_C_IDENTIFIER "contract_${stem}" test_name)
    set(result "${results}/${test_name}.xunit.xml")
    set(command "${python}" -m pytest "${contract}" -q -p no:cacheprovider --rootdir "${directory}"
      "--junitxml=${result}" -o "junit_suite_name=${PROJECT_NAME}.${test_name}" ${ARG_PYTEST_ARGS})
    if(COMMAND ament_add_test)
      ament_add_test("${test_name}"
        COMMAND ${command}
        RESULT_FILE "${result}"
        TIMEOUT "${ARG_TIMEOUT}"
        WORKING_DIRECTORY "${directory}"
        APPEND_ENV "AMENT_PREFIX_PATH=${CMAKE_INSTALL_PREFIX}")
    else()
      add_test(NAME "${test_name}" COMMAND ${command} WORKING_DIRECTORY "${directory}")
      set_tests_properties("${test_name}" PROPERTIES
        TIMEOUT "${ARG_TIMEOUT}"
        ENVIRONMENT "AMENT_PREFIX_PATH=${CMAKE_INSTALL_PREFIX}:$ENV{AMENT_PREFIX_PATH}")
    endif()
  endforeach()
endfunction()
