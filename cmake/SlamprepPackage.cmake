# The data folder the slamprep binary reads (core/paths.hpp, dataDir()) and the installed package:
#   share/slamprep/worlds/, share/slamprep/eval/suites/   worlds, scenarios, suites
#   lib/cmake/slamprep/                                  find_package(slamprep): slamprep::<library>
# Headers, libraries and the binary are installed by slamprep_library() and app/CMakeLists.txt.

# The binary looks for <exe_dir>/../share/slamprep, so bin/ and share/ must be siblings.
set(SLAMPREP_DATA_SUBDIR share/slamprep)
if(NOT CMAKE_INSTALL_BINDIR STREQUAL "bin")
  message(WARNING "slamprep: CMAKE_INSTALL_BINDIR is not 'bin'; the installed binary will not "
                  "find ${SLAMPREP_DATA_SUBDIR} by itself (set SLAMPREP_DATA_DIR when running it)")
endif()

# Build tree: the same layout beside the binary, as symlinks into the sources (edits show at once).
set(SLAMPREP_BUILD_DATA_DIR ${CMAKE_BINARY_DIR}/${SLAMPREP_DATA_SUBDIR})
file(MAKE_DIRECTORY ${SLAMPREP_BUILD_DATA_DIR}/eval)
file(CREATE_LINK ${SLAMPREP_ROOT}/worlds ${SLAMPREP_BUILD_DATA_DIR}/worlds SYMBOLIC)
file(CREATE_LINK ${SLAMPREP_ROOT}/eval/suites ${SLAMPREP_BUILD_DATA_DIR}/eval/suites SYMBOLIC)

install(DIRECTORY ${SLAMPREP_ROOT}/worlds/ DESTINATION ${SLAMPREP_DATA_SUBDIR}/worlds)
install(DIRECTORY ${SLAMPREP_ROOT}/eval/suites/ DESTINATION ${SLAMPREP_DATA_SUBDIR}/eval/suites
        FILES_MATCHING PATTERN "*.yaml")

# The CMake package. 0.x: a minor version may break the API, so only the same minor matches.
include(CMakePackageConfigHelpers)
set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/slamprep)
install(EXPORT slamprepTargets NAMESPACE slamprep:: DESTINATION ${config_dir})
configure_package_config_file(${SLAMPREP_ROOT}/cmake/slamprepConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/slamprepConfig.cmake
                              INSTALL_DESTINATION ${config_dir} PATH_VARS SLAMPREP_DATA_SUBDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/slamprepConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/slamprepConfig.cmake
              ${PROJECT_BINARY_DIR}/slamprepConfigVersion.cmake DESTINATION ${config_dir})
