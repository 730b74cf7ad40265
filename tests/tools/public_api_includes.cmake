# The dualform tool proves the public contract: its files include only the
# public headers (dualform/dualform.h, dualform/dualform_vulkan.h), the
# tool's own headers, the tools' JSON and environment modules, and
# core/status.hpp (the status type the tool shares with the engine; it needs
# nothing else of it). The files listed in `still_on_engine` have not moved
# to the C API yet; the list may only shrink.
#
# usage: cmake -DTOOL_DIR=tools/dualform -P public_api_includes.cmake
cmake_minimum_required(VERSION 3.25)
set(still_on_engine
  cmd_bench.cpp       # times the engine's internals (set-up, solve, drag) apart
  edit_report.cpp     # also writes the engine's figures, for cmd_bench
  edit_setup.cpp edit_setup.hpp
  pick_camera.cpp pick_camera.hpp
)
file(GLOB sources "${TOOL_DIR}/*.cpp" "${TOOL_DIR}/*.hpp")
set(bad "")
foreach(path IN LISTS sources)
  get_filename_component(name "${path}" NAME)
  if(name IN_LIST still_on_engine)
    continue()
  endif()
  file(STRINGS "${path}" includes REGEX "^#include \"")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^#include \"([^\"]+)\".*$" "\\1" header "${line}")
    if(header MATCHES "^dualform/(dualform|dualform_vulkan)\\.h$"
       OR header MATCHES "^(json|environment)/"
       OR header STREQUAL "core/status.hpp")
      continue()
    endif()
    if(header MATCHES "^dualform/(.+)$" AND EXISTS "${TOOL_DIR}/${CMAKE_MATCH_1}")
      get_filename_component(own "${CMAKE_MATCH_1}" NAME)
      if(NOT own IN_LIST still_on_engine)
        continue()
      endif()
    endif()
    string(APPEND bad "  ${name}: #include \"${header}\"\n")
  endforeach()
endforeach()
if(bad)
  message(FATAL_ERROR "tools/dualform reaches past the public API:\n${bad}")
endif()
list(LENGTH still_on_engine pending)
message(STATUS "tools/dualform: public API only, but for ${pending} files still on the engine")
