# The library graph's one rule, checked at configure time: core at the bottom, and no planner library
# reaching a verifier library through its links (or the reverse). Only the tools may see both sides.
get_property(_libraries GLOBAL PROPERTY TILTFIELD_LIBRARIES)

# Every tiltfield library `lib` reaches through its (public and private) links, into `out`.
function(tiltfield_reached lib out)
  set(_seen)
  set(_todo ${lib})
  while(_todo)
    list(POP_FRONT _todo _t)
    if(NOT TARGET ${_t} OR _t IN_LIST _seen)
      continue()
    endif()
    list(APPEND _seen ${_t})
    get_target_property(_links ${_t} LINK_LIBRARIES)
    if(_links)
      list(APPEND _todo ${_links})
    endif()
  endwhile()
  set(${out} ${_seen} PARENT_SCOPE)
endfunction()

foreach(_lib ${_libraries})
  get_target_property(_side ${_lib} TILTFIELD_SIDE)
  tiltfield_reached(${_lib} _reached)
  foreach(_dep ${_reached})
    if(NOT _dep IN_LIST _libraries OR _dep STREQUAL _lib)
      continue()
    endif()
    get_target_property(_dep_side ${_dep} TILTFIELD_SIDE)
    if((_side STREQUAL "planner" AND _dep_side STREQUAL "verifier") OR
       (_side STREQUAL "verifier" AND _dep_side STREQUAL "planner") OR
       (_side STREQUAL "core" AND NOT _dep_side STREQUAL "core") OR
       (NOT _side STREQUAL "tools" AND _dep_side STREQUAL "tools"))
      message(FATAL_ERROR "tiltfield: ${_lib} (${_side}) links ${_dep} (${_dep_side}); the planner's and the "
                          "verifier's libraries must not link each other, and only tools/ sees both")
    endif()
  endforeach()
endforeach()
