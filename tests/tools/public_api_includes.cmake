# The dualform tool proves the public contract: its files include only the
# public headers (dualform/dualform.h, dualform/dualform_vulkan.h), the
# tool's own headers and the tools' status type (status/tool_status.hpp),
# JSON and environment modules; nothing of the engine.
#
# usage: cmake -DTOOL_DIR=tools/dualform -P public_api_includes.cmake
cmake_minimum_required(VERSION 3.25)
file(GLOB sources "${TOOL_DIR}/*.cpp" "${TOOL_DIR}/*.hpp")
if(NOT sources)
  message(FATAL_ERROR "no sources in TOOL_DIR '${TOOL_DIR}'")
endif()
set(bad "")
foreach(path IN LISTS sources)
  get_filename_component(name "${path}" NAME)
  file(STRINGS "${path}" includes REGEX "^#include \"")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^#include \"([^\"]+)\".*$" "\\1" header "${line}")
    if(header MATCHES "^dualform/(dualform|dualform_vulkan)\\.h$"
       OR header MATCHES "^(json|environment|status)/")
      continue()
    endif()
    if(header MATCHES "^dualform/(.+)$" AND EXISTS "${TOOL_DIR}/${CMAKE_MATCH_1}")
      continue()
    endif()
    string(APPEND bad "  ${name}: #include \"${header}\"\n")
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "tools/dualform reaches past the public API:\n${bad}")
endif()
list(LENGTH sources checked)
message(STATUS "tools/dualform: ${checked} files, public API only")
