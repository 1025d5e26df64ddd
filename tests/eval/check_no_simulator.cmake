# cmake -DCLOSURE=a,b,... -DBINARY=... -DCONTROL_CLOSURE=... -DCONTROL_BINARY=... -P check_no_simulator.cmake
# Fails when the link closure (from CMake) or the shared libraries (from ldd) of BINARY hold the
# simulator, Embree or assimp. The control (test_sim, which links the simulator) must show them
# both ways, else the check is blind and fails too.
set(pattern "fmcw_sim|fmcw::sim|embree|assimp")
function(simulator_in closure binary out_closure out_ldd)
  string(REGEX MATCHALL "[^,]*(${pattern})[^,]*" hits "${closure}")
  set(${out_closure} "${hits}" PARENT_SCOPE)
  execute_process(COMMAND ldd "${binary}" OUTPUT_VARIABLE libs RESULT_VARIABLE failed)
  if(failed)
    message(FATAL_ERROR "ldd ${binary} failed")
  endif()
  string(REGEX MATCHALL "[^\n\t ]*(embree|assimp)[^\n\t ]*" so "${libs}")
  set(${out_ldd} "${so}" PARENT_SCOPE)
endfunction()

simulator_in("${CLOSURE}" "${BINARY}" in_closure in_ldd)
if(in_closure OR in_ldd)
  message(FATAL_ERROR "${BINARY} reaches the simulator: link closure [${in_closure}], shared libraries [${in_ldd}]")
endif()
simulator_in("${CONTROL_CLOSURE}" "${CONTROL_BINARY}" control_closure control_ldd)
if(NOT control_closure OR NOT control_ldd)
  message(FATAL_ERROR "the check is blind: ${CONTROL_BINARY} links the simulator, but link closure [${control_closure}], "
                      "shared libraries [${control_ldd}]")
endif()
message(STATUS "${BINARY}: no simulator, Embree or assimp (the control ${CONTROL_BINARY} has: ${control_ldd})")
