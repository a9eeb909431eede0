# Install tree: headers under include/rome/, the libraries, robots under share/rome/robots/, and a package config
# exporting rome::rome. Included from the top-level CMakeLists.txt after every library is defined.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ROME_LIBRARIES rome_framework rome_qp rome_nlp rome_collocation rome_riccati rome_multibody rome_rom rome_plants
    rome_planners rome_controllers rome_lqr rome_trajectory_optimization rome_posture rome_classic rome_stepping_stones_diagram)
foreach(lib ${ROME_LIBRARIES})
  # The source tree in the build, include/rome once installed (code includes "framework/system.h" etc.).
  set_property(TARGET ${lib} PROPERTY INTERFACE_INCLUDE_DIRECTORIES
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/rome>)
endforeach()
add_library(rome INTERFACE)
target_link_libraries(rome INTERFACE ${ROME_LIBRARIES})
add_library(rome::rome ALIAS rome)

install(TARGETS ${ROME_LIBRARIES} rome EXPORT romeTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
foreach(dir framework solvers systems diagrams)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rome/${dir} FILES_MATCHING PATTERN "*.h")
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/robots/ DESTINATION ${CMAKE_INSTALL_DATADIR}/rome/robots PATTERN "CMakeLists.txt" EXCLUDE)
install(EXPORT romeTargets NAMESPACE rome:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rome)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/romeConfig.cmake.in ${PROJECT_BINARY_DIR}/romeConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rome)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/romeConfigVersion.cmake VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/romeConfig.cmake ${PROJECT_BINARY_DIR}/romeConfigVersion.cmake DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rome)
