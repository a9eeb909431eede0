# Install tree: headers under include/rome/, the libraries under lib/, robots under share/rome/robots/, and a package
# config with three components (cmake/romeConfig.cmake.in):
#   core  rome::core  the framework (systems, diagrams, hybrid simulator, Linearize), the QP and Riccati solvers and
#                     the LQR: needs Eigen and SUNDIALS only (no Ipopt, Bullet or urdfdom)
#   nlp   rome::nlp   core + the NLP (Ipopt) and direct-collocation solvers, and collocation dynamics from a system
#   all   rome::rome  every library: plants, ROMs, planners, controllers, visualization, the three diagrams (default)
# Included from the top-level CMakeLists.txt after every library is defined. The install is relocatable: nothing in it
# names the build machine's folders, and robots are found relative to lib/librome_location.so (install_location.h).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ROME_CORE_LIBRARIES rome_framework rome_location rome_qp rome_riccati rome_lqr)
set(ROME_NLP_LIBRARIES rome_nlp rome_collocation rome_trajectory_optimization)
set(ROME_ALL_LIBRARIES rome_multibody rome_rom rome_plants rome_perturbations rome_planners rome_controllers rome_posture rome_classic
    rome_visualization rome_stepping_stones_diagram rome_walking_diagram rome_hopping_diagram)
set(ROME_LIBRARIES ${ROME_CORE_LIBRARIES} ${ROME_NLP_LIBRARIES} ${ROME_ALL_LIBRARIES})
if(TARGET rome_python)
  # The Python module (python/) is a shared object that links every library: they must be position-independent.
  set_property(TARGET ${ROME_LIBRARIES} PROPERTY POSITION_INDEPENDENT_CODE ON)
endif()
foreach(lib ${ROME_LIBRARIES})
  # The source tree in the build, include/rome once installed (code includes "framework/system.h" etc.).
  set_property(TARGET ${lib} PROPERTY INTERFACE_INCLUDE_DIRECTORIES
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/rome>)
endforeach()
add_library(rome_core INTERFACE)
target_link_libraries(rome_core INTERFACE ${ROME_CORE_LIBRARIES})
set_target_properties(rome_core PROPERTIES EXPORT_NAME core)
add_library(rome::core ALIAS rome_core)
add_library(rome_nlp_component INTERFACE)
target_link_libraries(rome_nlp_component INTERFACE rome_core ${ROME_NLP_LIBRARIES})
set_target_properties(rome_nlp_component PROPERTIES EXPORT_NAME nlp)
add_library(rome::nlp ALIAS rome_nlp_component)
add_library(rome INTERFACE)
target_link_libraries(rome INTERFACE rome_nlp_component ${ROME_ALL_LIBRARIES})
add_library(rome::rome ALIAS rome)

set(destinations ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS ${ROME_CORE_LIBRARIES} rome_core EXPORT romeCoreTargets ${destinations})
install(TARGETS ${ROME_NLP_LIBRARIES} rome_nlp_component EXPORT romeNlpTargets ${destinations})
install(TARGETS ${ROME_ALL_LIBRARIES} rome EXPORT romeTargets ${destinations})
foreach(dir framework solvers systems diagrams)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rome/${dir} FILES_MATCHING PATTERN "*.h")
endforeach()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/robots/ DESTINATION ${CMAKE_INSTALL_DATADIR}/rome/robots PATTERN "CMakeLists.txt" EXCLUDE)
foreach(set romeCoreTargets romeNlpTargets romeTargets)
  install(EXPORT ${set} NAMESPACE rome:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rome)
endforeach()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/romeConfig.cmake.in ${PROJECT_BINARY_DIR}/romeConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rome)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/romeConfigVersion.cmake VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/romeConfig.cmake ${PROJECT_BINARY_DIR}/romeConfigVersion.cmake DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/rome)
