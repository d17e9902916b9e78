# Installation: the `stepstone` binary, the libraries with their headers, the
# schema, statements and queries, a CMake package (find_package(stepstone),
# targets stepstone::core ... stepstone::service) and a pkg-config file.
# Included from the top-level CMakeLists.txt after every target exists.
include(CMakePackageConfigHelpers)

# the installable libraries in dependency order (bench is the binary's own)
set(STEPSTONE_INSTALLED_MODULES core sim nn evo kb db stats exp report service)
set(installed_targets stepstone_flags)
foreach(module ${STEPSTONE_INSTALLED_MODULES})
    set_target_properties(stepstone_${module} PROPERTIES EXPORT_NAME ${module})
    list(APPEND installed_targets stepstone_${module})
endforeach()
# linked PRIVATE by every library, so static consumers need it in the export set
set_target_properties(stepstone_flags PROPERTIES EXPORT_NAME flags)

install(TARGETS stepstone RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS ${installed_targets} EXPORT stepstoneTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/stepstone)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/lib/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/stepstone
    FILES_MATCHING PATTERN "*.hpp"
    PATTERN "bench" EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/schema ${PROJECT_SOURCE_DIR}/sql ${PROJECT_SOURCE_DIR}/queries
    DESTINATION ${CMAKE_INSTALL_DATADIR}/stepstone)

set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/stepstone)
install(EXPORT stepstoneTargets NAMESPACE stepstone:: DESTINATION ${config_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/stepstoneConfig.cmake.in
    ${PROJECT_BINARY_DIR}/stepstoneConfig.cmake INSTALL_DESTINATION ${config_dir}
    PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/stepstoneConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/stepstoneConfig.cmake ${PROJECT_BINARY_DIR}/stepstoneConfigVersion.cmake
    DESTINATION ${config_dir})

file(RELATIVE_PATH STEPSTONE_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
configure_file(${PROJECT_SOURCE_DIR}/cmake/stepstone.pc.in ${PROJECT_BINARY_DIR}/stepstone.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/stepstone.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
