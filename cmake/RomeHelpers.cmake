# Helpers shared by every CMakeLists.txt in ROME.

# Adds every immediate subdirectory of the current source dir that has a CMakeLists.txt.
# Developers may skip work-in-progress folders with -DROME_SKIP_SUBDIRS="tests/benchmarks/qp;...".
function(rome_add_child_directories)
  file(GLOB children LIST_DIRECTORIES true RELATIVE ${CMAKE_CURRENT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR}/*)
  list(SORT children)
  foreach(child ${children})
    file(RELATIVE_PATH rel ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR}/${child})
    if(rel IN_LIST ROME_SKIP_SUBDIRS)
      message(STATUS "ROME: skipping ${rel} (ROME_SKIP_SUBDIRS)")
    elseif(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/${child} AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/${child}/CMakeLists.txt)
      add_subdirectory(${child})
    endif()
  endforeach()
endfunction()

# rome_test_source: rome::test::SourcePath (tests/common/source_path.h), the only code that knows the repository root
# (ROME_SOURCE_DIR). Tests and benchmarks link it; made by the first rome_add_test / rome_add_benchmark.
function(rome_test_source_library)
  if(NOT TARGET rome_test_source)
    add_library(rome_test_source STATIC ${PROJECT_SOURCE_DIR}/tests/common/source_path.cc)
    target_include_directories(rome_test_source PUBLIC ${PROJECT_SOURCE_DIR})
    target_compile_definitions(rome_test_source PRIVATE ROME_SOURCE_DIR="${PROJECT_SOURCE_DIR}" ROME_BINARY_DIR="${PROJECT_BINARY_DIR}")
    target_link_libraries(rome_test_source PUBLIC rome_framework)
  endif()
endfunction()

# rome_add_test(NAME <name> SOURCES <files...> LIBS <targets...> [LABELS <labels...>] [SHARDS <n>])
# Builds a GoogleTest executable and registers it with ctest.
# Tests run with the repository root as working directory, so robots/... paths resolve.
# SHARDS n (n >= 2) registers n ctest entries <name>_shard<i>, each running every n-th test case (GoogleTest's own
# GTEST_TOTAL_SHARDS / GTEST_SHARD_INDEX), so `ctest -j` spreads a long closed-loop test over the cores.
function(rome_add_test)
  cmake_parse_arguments(T "" "NAME;SHARDS" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${T_NAME} ${T_SOURCES})
  rome_test_source_library()
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} rome_test_source GTest::gtest GTest::gtest_main)
  if(T_SHARDS AND T_SHARDS GREATER 1)
    math(EXPR last "${T_SHARDS} - 1")
    foreach(i RANGE ${last})
      add_test(NAME ${T_NAME}_shard${i} COMMAND ${T_NAME} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
      set_tests_properties(${T_NAME}_shard${i} PROPERTIES ENVIRONMENT "GTEST_TOTAL_SHARDS=${T_SHARDS};GTEST_SHARD_INDEX=${i}")
      if(T_LABELS)
        set_tests_properties(${T_NAME}_shard${i} PROPERTIES LABELS "${T_LABELS}")
      endif()
    endforeach()
  else()
    add_test(NAME ${T_NAME} COMMAND ${T_NAME} WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
    if(T_LABELS)
      set_tests_properties(${T_NAME} PROPERTIES LABELS "${T_LABELS}")
    endif()
  endif()
endfunction()

# rome_add_benchmark(NAME <name> SOURCES <files...> LIBS <targets...>)
# Google Benchmark executable; not run by ctest (performance is measured, never asserted).
function(rome_add_benchmark)
  cmake_parse_arguments(B "" "NAME" "SOURCES;LIBS" ${ARGN})
  add_executable(${B_NAME} ${B_SOURCES})
  rome_test_source_library()
  target_link_libraries(${B_NAME} PRIVATE ${B_LIBS} rome_test_source benchmark::benchmark)
endfunction()
