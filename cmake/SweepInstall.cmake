# `cmake --install`: the three tools, and the runtime as a CMake package (find_package(sweep),
# target sweep::runtime) with its headers under include/sweep, used as #include "sweep/sim/simulator.h";
# and libsweep, the runtime behind a C interface (target sweep::sweep, #include "sweep/sweep.h").
# The runtime is the four layers core < bind < sim < io (README, "Layout"): Eigen, nlohmann-json
# and OpenMP, no authoring library. tools/check-runtime.sh builds examples/runtime against it.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(SWEEP_RUNTIME_MODULES core bind sim io)
add_library(sweep_runtime INTERFACE)
set_target_properties(sweep_runtime PROPERTIES EXPORT_NAME runtime)
foreach(module IN LISTS SWEEP_RUNTIME_MODULES)
  target_link_libraries(sweep_runtime INTERFACE sweep_${module})
  set_target_properties(sweep_${module} PROPERTIES EXPORT_NAME ${module})
  install(DIRECTORY lib/${module}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sweep/${module}
          FILES_MATCHING PATTERN "*.h" PATTERN "*_detail.h" EXCLUDE)
endforeach()
add_library(sweep::runtime ALIAS sweep_runtime)

install(TARGETS sweep_runtime sweep_core sweep_bind sweep_sim sweep_io EXPORT sweepTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS sweep EXPORT sweepTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES lib/capi/include/sweep/sweep.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/sweep)
install(TARGETS sweep-fit sweep-bind sweep-sim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT sweepTargets NAMESPACE sweep:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sweep)
configure_package_config_file(cmake/sweepConfig.cmake.in ${CMAKE_CURRENT_BINARY_DIR}/sweepConfig.cmake
                              INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sweep)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/sweepConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/sweepConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/sweepConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/sweep)
