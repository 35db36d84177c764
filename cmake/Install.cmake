# `cmake --install build/release --prefix P`: the needlesim program (bin/), the public
# C++ API (lib/libneedlesim.so, include/needlesim/needlesim.hpp) and its CMake package
# (lib/cmake/needlesim: find_package(needlesim), target needlesim::needlesim).
include(CMakePackageConfigHelpers)
set(NEEDLESIM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/needlesim)

# The program links the static needlesim_lib: it needs no library of the prefix at run time.
install(TARGETS needlesim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS needlesim_shared EXPORT needlesimTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES ${PROJECT_SOURCE_DIR}/src/needlesim/needlesim.hpp DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/needlesim)
install(EXPORT needlesimTargets NAMESPACE needlesim:: DESTINATION ${NEEDLESIM_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/needlesimConfig.cmake.in
  ${PROJECT_BINARY_DIR}/needlesimConfig.cmake INSTALL_DESTINATION ${NEEDLESIM_CMAKE_DIR}
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/needlesimConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/needlesimConfig.cmake ${PROJECT_BINARY_DIR}/needlesimConfigVersion.cmake
  DESTINATION ${NEEDLESIM_CMAKE_DIR})
