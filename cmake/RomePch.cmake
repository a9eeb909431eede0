# Precompiled headers (ours). Eigen, the standard library and GoogleTest are parsed again by nearly every one of the
# ~200 translation units: about 2 s of the compiler's time each at -O2. Two precompiled headers, one for the
# libraries, examples and benchmarks and one for the tests (with <gtest/gtest.h>), are built once and reused by every
# target (REUSE_FROM: the same global flags). A target that could not use them would still compile: the compiler
# then reads the headers themselves. -DROME_PCH=OFF turns them off; the fuzz build (clang) never uses them.
option(ROME_PCH "Precompile the Eigen, standard-library and GoogleTest headers" ON)

set(ROME_PCH_HEADERS <algorithm> <array> <cmath> <cstdint> <cstdio> <functional> <map> <memory> <optional> <sstream>
    <stdexcept> <string> <utility> <vector> <Eigen/Dense>)

# Translation units that compile without the precompiled headers (pairs: target, file): with them, GCC 12 reports
# false -Warray-bounds / -Wstringop-overflow warnings in libstdc++'s std::string copies (memcpy through char_traits.h),
# which it does not report when it reads the same headers as text (measured 2026-12-03, -O3).
set(ROME_PCH_SKIP
    rome_stepping_stones_diagram "diagrams/stepping_stones/stepping_stones_output_adapter.cc"
    rome_example_support "examples/common/cli.cc"
    rome_example_support "examples/common/cli_scenario.cc"
    rome_visualization "systems/visualization/animation.cc"
    controllers_task_space_qp_controller_allocation_test "tests/systems/controllers/task_space_qp_controller_allocation_test.cc"
    rome_test_source "tests/common/source_path.cc")

# rome_apply_precompiled_headers(): after every target is defined (the top-level CMakeLists.txt calls it last).
function(rome_apply_precompiled_headers)
  if(NOT ROME_PCH OR ROME_FUZZ)
    return()
  endif()
  add_library(rome_pch OBJECT ${PROJECT_SOURCE_DIR}/cmake/pch/rome_pch.cc)
  target_link_libraries(rome_pch PRIVATE Eigen3::Eigen)
  target_precompile_headers(rome_pch PRIVATE ${ROME_PCH_HEADERS})
  set(have_tests OFF)
  if(ROME_BUILD_TESTS)
    set(have_tests ON)
    add_library(rome_test_pch OBJECT ${PROJECT_SOURCE_DIR}/cmake/pch/rome_pch.cc)
    target_link_libraries(rome_test_pch PRIVATE Eigen3::Eigen GTest::gtest)
    target_precompile_headers(rome_test_pch PRIVATE ${ROME_PCH_HEADERS} <gtest/gtest.h>)
  endif()
  list(LENGTH ROME_PCH_SKIP n)
  math(EXPR last "${n} - 1")
  foreach(i RANGE 0 ${last} 2)
    math(EXPR j "${i} + 1")
    list(GET ROME_PCH_SKIP ${i} target)
    list(GET ROME_PCH_SKIP ${j} file)
    if(TARGET ${target})
      set_source_files_properties(${PROJECT_SOURCE_DIR}/${file} TARGET_DIRECTORY ${target} PROPERTIES SKIP_PRECOMPILE_HEADERS ON)
    endif()
  endforeach()
  rome_collect_targets(${PROJECT_SOURCE_DIR} targets)
  foreach(t ${targets})
    get_target_property(type ${t} TYPE)
    # A shared library (rome_location) compiles with -fPIC, which a header precompiled without it cannot serve.
    if(NOT type MATCHES "^(STATIC_LIBRARY|OBJECT_LIBRARY|EXECUTABLE)$" OR t MATCHES "^rome_(test_)?pch$")
      continue()
    endif()
    get_target_property(libs ${t} LINK_LIBRARIES)
    get_target_property(pic ${t} POSITION_INDEPENDENT_CODE)
    target_link_libraries(${t} PRIVATE Eigen3::Eigen)  # the headers' include path, were the compiler to read them
    if(have_tests AND libs AND "GTest::gtest" IN_LIST libs)
      target_precompile_headers(${t} REUSE_FROM rome_test_pch)
    elseif(pic)
      # The static libraries that the Python module links (python/) compile with -fPIC: their own header, built so.
      if(NOT TARGET rome_pic_pch)
        add_library(rome_pic_pch OBJECT ${PROJECT_SOURCE_DIR}/cmake/pch/rome_pch.cc)
        target_link_libraries(rome_pic_pch PRIVATE Eigen3::Eigen)
        target_precompile_headers(rome_pic_pch PRIVATE ${ROME_PCH_HEADERS})
        set_target_properties(rome_pic_pch PROPERTIES POSITION_INDEPENDENT_CODE ON)
      endif()
      target_precompile_headers(${t} REUSE_FROM rome_pic_pch)
    else()
      target_precompile_headers(${t} REUSE_FROM rome_pch)
    endif()
  endforeach()
endfunction()

# rome_collect_targets(DIR OUT): every target defined in DIR and the directories below it.
function(rome_collect_targets dir out)
  get_property(found DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  get_property(children DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(child ${children})
    rome_collect_targets(${child} below)
    list(APPEND found ${below})
  endforeach()
  set(${out} ${found} PARENT_SCOPE)
endfunction()
