# Records the version and git revision in a generated header.
find_package(Git QUIET)
set(NEEDLESIM_GIT_REVISION "unknown")
if(GIT_FOUND AND EXISTS "${CMAKE_SOURCE_DIR}/.git")
  execute_process(COMMAND ${GIT_EXECUTABLE} describe --always --dirty --tags
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} OUTPUT_VARIABLE NEEDLESIM_GIT_REVISION
    OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
  if(NOT NEEDLESIM_GIT_REVISION)
    set(NEEDLESIM_GIT_REVISION "unknown")
  endif()
endif()
configure_file(${CMAKE_SOURCE_DIR}/src/needlesim/core/version.hpp.in
  ${CMAKE_BINARY_DIR}/generated/needlesim/core/version.hpp @ONLY)
