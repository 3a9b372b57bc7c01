# Helpers that keep every library and program's CMakeLists.txt to a few lines.

# Warnings for our own code only (MRPT/OpenCV headers are included as SYSTEM).
function(quasiloc_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
endfunction()

# quasiloc_library(<name> DEPENDS <targets...>)
# Builds libs/<name>/src/*.cpp (without *_unittest.cpp) into target quasiloc_<name>
# (alias quasiloc::<name>), and the unit tests src/*_unittest.cpp into
# bin/<name>_unittests, registered with ctest one test per TEST().
function(quasiloc_library name)
  cmake_parse_arguments(ARG "" "" "DEPENDS;TEST_DEPENDS" ${ARGN})
  set(dir ${CMAKE_CURRENT_SOURCE_DIR})
  file(GLOB all_sources CONFIGURE_DEPENDS ${dir}/src/*.cpp)
  set(lib_sources "")
  set(test_sources "")
  foreach(src ${all_sources})
    if(src MATCHES "_unittest\\.cpp$")
      list(APPEND test_sources ${src})
    else()
      list(APPEND lib_sources ${src})
    endif()
  endforeach()
  if(NOT lib_sources)
    message(WARNING "libs/${name} has no sources yet: library skipped")
    return()
  endif()
  set(target quasiloc_${name})
  add_library(${target} STATIC ${lib_sources})
  add_library(quasiloc::${name} ALIAS ${target})
  target_include_directories(${target} PUBLIC ${dir}/include)
  target_include_directories(${target} SYSTEM PUBLIC ${OpenCV_INCLUDE_DIRS})
  target_link_libraries(${target} PUBLIC ${ARG_DEPENDS})
  target_compile_definitions(${target} PUBLIC QUASILOC_SHARED_DIR="${QUASILOC_SHARED_DIR}"
    QUASILOC_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  quasiloc_set_warnings(${target})

  if(QUASILOC_BUILD_TESTS AND test_sources)
    set(test_target ${name}_unittests)
    add_executable(${test_target} ${test_sources})
    target_link_libraries(${test_target} PRIVATE ${target} ${ARG_TEST_DEPENDS} GTest::gtest GTest::gtest_main)
    quasiloc_set_warnings(${test_target})
    gtest_discover_tests(${test_target} TEST_PREFIX "${name}." DISCOVERY_TIMEOUT 60
      WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
  endif()
endfunction()

# quasiloc_program(<name> SOURCES <files...> DEPENDS <targets...>)
function(quasiloc_program name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPENDS})
  quasiloc_set_warnings(${name})
endfunction()
