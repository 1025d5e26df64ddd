# `cmake --install`: the fmcw CLI, the libraries and headers of fmcw::core and fmcw::io, and a
# CMake package (fmcwConfig.cmake, fmcwConfigVersion.cmake, fmcwTargets.cmake) under
# lib/cmake/fmcw. The Python module installs itself (python/CMakeLists.txt, component python).
# fmcw::sim and fmcw::eval are not installed: they are the simulator and the evaluation behind
# the CLI, not parts to embed (and would bring Embree and assimp into a consumer's link).
include(CMakePackageConfigHelpers)

set(FMCW_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/fmcw)
set(fmcw_installed_targets fmcw_core)
# The installed static libraries hold machine code beside GCC's LTO bytecode, so that a consumer
# links them without link-time optimisation (quickly, and with any compiler), while the
# project's own programs still optimise across them.
function(fmcw_fat_lto_objects target)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND FMCW_IPO_SUPPORTED AND FMCW_LTO AND NOT FMCW_SANITIZE AND NOT FMCW_FUZZ)
    target_compile_options(${target} PRIVATE $<$<CONFIG:Release,RelWithDebInfo>:-ffat-lto-objects>)
  endif()
endfunction()
fmcw_fat_lto_objects(fmcw_core)
set(FMCW_INSTALL_IO OFF)
set(FMCW_INSTALL_LIBZIP OFF)  # io reads .npz through libzip, found with pkg-config
if(TARGET fmcw_io)
  get_target_property(fmcw_io_links fmcw_io LINK_LIBRARIES)
  if("PkgConfig::LIBZIP" IN_LIST fmcw_io_links)
    set(FMCW_INSTALL_LIBZIP ON)
  endif()
endif()
if(TARGET fmcw_io)
  list(APPEND fmcw_installed_targets fmcw_io)
  fmcw_fat_lto_objects(fmcw_io)
  set(FMCW_INSTALL_IO ON)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/io/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/core/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT dev)
install(TARGETS ${fmcw_installed_targets} EXPORT fmcwTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
if(TARGET fmcw)
  install(TARGETS fmcw RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT cli)
endif()
install(EXPORT fmcwTargets NAMESPACE fmcw:: DESTINATION ${FMCW_CMAKE_INSTALL_DIR} COMPONENT dev)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/fmcwConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/fmcwConfig.cmake INSTALL_DESTINATION ${FMCW_CMAKE_INSTALL_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/fmcwConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/fmcwConfig.cmake ${PROJECT_BINARY_DIR}/fmcwConfigVersion.cmake
        DESTINATION ${FMCW_CMAKE_INSTALL_DIR} COMPONENT dev)
