include(CheckIPOSupported)
check_ipo_supported(RESULT FMCW_IPO_SUPPORTED OUTPUT FMCW_IPO_MESSAGE LANGUAGES CXX)

# Precompiled headers (FMCW_PCH), not in the fuzz build: Eigen's headers alone take several
# seconds of every file's compile, and nearly every file includes them through the project's
# headers. The test programs add GoogleTest.
function(fmcw_precompile_headers target)
  if(FMCW_PCH AND NOT FMCW_FUZZ)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()

# One place for compiler settings on the project's own targets.
function(fmcw_target_settings target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ON)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Werror)
  # Link-time optimisation in optimised builds: small functions of other files (noise draws,
  # intensity) inline into the per-pixel loops.
  if(FMCW_IPO_SUPPORTED AND FMCW_LTO AND NOT FMCW_SANITIZE AND NOT FMCW_FUZZ)
    set_target_properties(${target} PROPERTIES INTERPROCEDURAL_OPTIMIZATION_RELEASE ON
                                               INTERPROCEDURAL_OPTIMIZATION_RELWITHDEBINFO ON)
  endif()
  # Undefined behaviour stops the program (no recovery), so that a test or fuzz run fails on it
  # instead of printing a line nobody reads.
  if(FMCW_SANITIZE OR FMCW_FUZZ)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-sanitize-recover=all
                                             -fno-omit-frame-pointer)
    target_link_options(${target} PUBLIC -fsanitize=address,undefined -fno-sanitize-recover=all)
    # GCC's flow analysis sees through ASan's instrumentation badly and warns of uninitialised
    # members inside libstdc++ (std::regex) that are initialised: not errors in this build.
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
      target_compile_options(${target} PRIVATE -Wno-maybe-uninitialized)
    endif()
  endif()
  get_target_property(type ${target} TYPE)
  if(NOT type STREQUAL "MODULE_LIBRARY")  # Python.h must come before any standard header
    fmcw_precompile_headers(${target} <algorithm> <cmath> <cstdint> <memory> <string> <vector> <Eigen/Core>
                            <Eigen/Geometry>)
  endif()
  # Coverage feedback for libFuzzer in every library a fuzz target reaches.
  if(FMCW_FUZZ)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()
