# `cmake --install BUILD [--prefix DIR]`: the libraries, their headers under include/splam, the
# splam program, and a CMake package (find_package(splam), splam:: targets; see
# cmake/splamConfig.cmake.in). examples/out_of_tree/ is a project built against it.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
set(SPLAM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/splam)
foreach(module kernel sim graph estimation exploration io runtime studies cli)
  set_target_properties(splam_${module} PROPERTIES EXPORT_NAME ${module})
endforeach()
# splam_warnings is an interface library of compile options; the static libraries name it as a
# link-only dependency, which the export set must hold (it adds nothing to a consumer's link).
install(TARGETS splam_kernel splam_sim splam_graph splam_estimation splam_exploration splam_io
                splam_runtime splam_studies splam_cli splam_warnings splam
        EXPORT splamTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY kernel sim graph estimation exploration io runtime studies
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/splam
        FILES_MATCHING PATTERN "*.h")
install(FILES apps/cli.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/splam/apps)
install(EXPORT splamTargets NAMESPACE splam:: DESTINATION ${SPLAM_CMAKE_DIR})
configure_package_config_file(cmake/splamConfig.cmake.in
                              ${CMAKE_CURRENT_BINARY_DIR}/splamConfig.cmake
                              INSTALL_DESTINATION ${SPLAM_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/splamConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/splamConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/splamConfigVersion.cmake
        DESTINATION ${SPLAM_CMAKE_DIR})
