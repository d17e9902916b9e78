# Installation: the `stepstone` binary, the libraries with their headers, the
# schema, statements and queries, a CMake package (find_package(stepstone),
# targets stepstone::core ... stepstone::service) and a pkg-config file.
# Included from the top-level CMakeLists.txt after every target exists.
include(CMakePackageConfigHelpers)

# the installable libraries in dependency order (bench/ and reference/ are not the library's)
set(STEPSTONE_INSTALLED_MODULES core sim nn evo kb db stats runs exp report service)
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
    FILES_MATCHING PATTERN "*.hpp")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/schema ${PROJECT_SOURCE_DIR}/sql ${PROJECT_SOURCE_DIR}/queries
    DESTINATION ${CMAKE_INSTALL_DATADIR}/stepstone)

# a sanitized build's libraries need the sanitizer runtimes in whatever links them,
# and a build with Open MPI its C library
set(STEPSTONE_PC_EXTRA_LIBS "")
set(STEPSTONE_PC_REQUIRES "")
set(STEPSTONE_CONFIG_MPI "")
if(STEPSTONE_HAVE_MPI)
    set(STEPSTONE_PC_REQUIRES " mpi-c")
    # FindMPI's C component needs the consumer to enable C; without it, pkg-config's mpi-c
    string(CONCAT STEPSTONE_CONFIG_MPI
        "get_property(stepstone_languages GLOBAL PROPERTY ENABLED_LANGUAGES)\n"
        "if(\"C\" IN_LIST stepstone_languages)\n"
        "    find_dependency(MPI COMPONENTS C)\n"
        "elseif(NOT TARGET MPI::MPI_C)\n"
        "    pkg_check_modules(STEPSTONE_MPI_C REQUIRED QUIET IMPORTED_TARGET mpi-c)\n"
        "    add_library(MPI::MPI_C INTERFACE IMPORTED)\n"
        "    target_link_libraries(MPI::MPI_C INTERFACE PkgConfig::STEPSTONE_MPI_C)\n"
        "endif()")
endif()
if(STEPSTONE_SANITIZE)
    set(STEPSTONE_PC_EXTRA_LIBS "-fsanitize=address,undefined")
endif()
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
