# cmake --install: headers under include/ceilnav (so that consumers include
# "host/driver.hpp" as the project does), the libraries, the ceilnav program
# and a CMake package (find_package(ceilnav), targets ceilnav::*).
include(CMakePackageConfigHelpers)

set(ceilnav_exported ceilnav_warnings ceilnav_common ceilnav_fixedpoint ceilnav_regs ceilnav_stream
                     ceilnav_host ceilnav_drivers ceilnav_golden ceilnav_host_pattern
                     ceilnav_golden_pattern ceilnav_nav)
foreach(t IN LISTS ceilnav_exported)
  string(REGEX REPLACE "^ceilnav_" "" short ${t})
  set_target_properties(${t} PROPERTIES EXPORT_NAME ${short})
endforeach()
install(TARGETS ${ceilnav_exported} EXPORT ceilnavTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CEILNAV_INSTALL_INCLUDEDIR})
install(TARGETS ceilnav RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

foreach(dir IN ITEMS common fixedpoint stream host drivers golden nav)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${CEILNAV_INSTALL_INCLUDEDIR}/${dir}
          FILES_MATCHING PATTERN "*.hpp" PATTERN "tests" EXCLUDE
          PATTERN "rtl_backend.hpp" EXCLUDE PATTERN "verilated_*.hpp" EXCLUDE)  # need Verilator
endforeach()
install(FILES ${CEILNAV_GENERATED_DIR}/ceilnav/regs.hpp ${CEILNAV_GENERATED_DIR}/ceilnav/regblock.hpp
              ${CEILNAV_GENERATED_DIR}/ceilnav/ceilnav_regs.h
        DESTINATION ${CEILNAV_INSTALL_INCLUDEDIR}/ceilnav)

set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/ceilnav)
install(EXPORT ceilnavTargets NAMESPACE ceilnav:: DESTINATION ${config_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ceilnavConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/ceilnavConfig.cmake
                              INSTALL_DESTINATION ${config_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ceilnavConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/ceilnavConfig.cmake
              ${PROJECT_BINARY_DIR}/ceilnavConfigVersion.cmake DESTINATION ${config_dir})

# The example consumer, built against an installed tree (docs/architecture.md).
if(CEILNAV_BUILD_TESTS)
  add_test(NAME install.example_consumer
           COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${PROJECT_BINARY_DIR}
                   -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
                   -DWORK_DIR=${PROJECT_BINARY_DIR}/install_test -P
                   ${PROJECT_SOURCE_DIR}/cmake/check_install.cmake)
  set_tests_properties(install.example_consumer PROPERTIES LABELS slow TIMEOUT 600)
endif()
