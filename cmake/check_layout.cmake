# The layout's rules, run as a test (cmake -DROOT=<source dir> -P check_layout.cmake):
#  1. each capability's sources and public headers include only the public headers of the capabilities
#     its library links (tiltfield/<capability>/...), and nothing by a relative path out of its folder;
#  2. no C++ file is longer than 600 lines;
#  3. no code or build file names a document outside the repository.
# Every broken rule is printed; the script fails when there is one.
cmake_minimum_required(VERSION 3.20)
if(NOT ROOT)
  message(FATAL_ERROR "usage: cmake -DROOT=<tiltfield source dir> -P check_layout.cmake")
endif()

# folder (from ROOT) -> capabilities whose headers it may include. Mirrors the libraries' links.
set(_folders
  core include/tiltfield/core
  planner/tilt include/tiltfield/tilt
  planner/replan include/tiltfield/replan
  planner/post include/tiltfield/post
  planner/offset include/tiltfield/offset
  verifier/gcode include/tiltfield/gcode
  verifier/dexel include/tiltfield/dexel
  verifier/engagement include/tiltfield/engagement
  verifier/grind include/tiltfield/grind
  tools/scenes tools/report)
set(_allowed_core core)
set(_allowed_tilt core tilt)
set(_allowed_replan core tilt replan)
set(_allowed_post core post)
set(_allowed_offset core offset)
set(_allowed_gcode core gcode)
set(_allowed_dexel core dexel)
set(_allowed_engagement core dexel engagement)
set(_allowed_grind core grind)
set(_allowed_scenes core)
set(_allowed_report core gcode)

set(_errors 0)
macro(layout_error text)
  message("layout: ${text}")
  math(EXPR _errors "${_errors} + 1")
endmacro()

foreach(_folder ${_folders})
  get_filename_component(_capability ${_folder} NAME)
  set(_allowed ${_allowed_${_capability}})
  file(GLOB _files ${ROOT}/${_folder}/*.cpp ${ROOT}/${_folder}/*.hpp ${ROOT}/${_folder}/internal/*.hpp)
  foreach(_file ${_files})
    file(RELATIVE_PATH _rel ${ROOT} ${_file})
    file(STRINGS ${_file} _includes REGEX "^#include \"")
    foreach(_line ${_includes})
      if(_line MATCHES "^#include \"tiltfield/([a-z_]+)/")
        if(NOT CMAKE_MATCH_1 IN_LIST _allowed)
          layout_error("${_rel} includes ${_line}: ${_capability} does not link ${CMAKE_MATCH_1}")
        endif()
      elseif(_line MATCHES "^#include \"\\.\\./")
        layout_error("${_rel}: ${_line} reaches out of its folder")
      endif()
    endforeach()
  endforeach()
endforeach()

file(GLOB_RECURSE _code ${ROOT}/core/* ${ROOT}/planner/* ${ROOT}/verifier/* ${ROOT}/tools/* ${ROOT}/include/*
                        ${ROOT}/tests/* ${ROOT}/cmake/* ${ROOT}/scenes/*)
list(FILTER _code INCLUDE REGEX "\\.(cpp|hpp|cmake|js|mjs|sh)$|/CMakeLists\\.txt$")
list(FILTER _code EXCLUDE REGEX "/node_modules/|/check_layout\\.cmake$")
list(APPEND _code ${ROOT}/CMakeLists.txt ${ROOT}/dev)
foreach(_file ${_code})
  file(RELATIVE_PATH _rel ${ROOT} ${_file})
  if(_file MATCHES "\\.(cpp|hpp)$")
    file(STRINGS ${_file} _lines)
    list(LENGTH _lines _n)
    if(_n GREATER 600)
      layout_error("${_rel} has ${_n} lines (split it: at most 600)")
    endif()
  endif()
  file(STRINGS ${_file} _refs REGEX "\\.\\./shared|[Ss]eed [0-9]|[Ss]eed's|[Ii]ssue [0-9]+")
  foreach(_ref ${_refs})
    string(STRIP "${_ref}" _ref)
    layout_error("${_rel} names a document outside the repository: ${_ref}")
  endforeach()
endforeach()

if(_errors GREATER 0)
  message(FATAL_ERROR "layout: ${_errors} rule(s) broken")
endif()
message("layout: every rule holds")
