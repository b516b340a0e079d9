# `cmake --install`: the public headers, the libraries, the CMake package (rgvcConfig.cmake,
# rgvcConfigVersion.cmake, one targets file per part) and rgvc.pc. Included by the top-level CMakeLists
# (RGVC_INSTALL). Consumers: find_package(rgvc 0.2 CONFIG REQUIRED [COMPONENTS render gl]), then
# rgvc::rgvc (grid + dynamics), rgvc::render, rgvc::render_gl; tests/consumer checks both ways in.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(RGVC_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/rgvc CACHE STRING
  "Where rgvcConfig.cmake goes, relative to the install prefix")
mark_as_advanced(RGVC_INSTALL_CMAKEDIR)

# Headers. grid/internal is private (the libraries' own stages) and never installed; the GL stage's
# headers only when it is built.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/grid/include/ ${PROJECT_SOURCE_DIR}/dynamics/include/
        ${RGVC_GENERATED_INCLUDE_DIR}/
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT rgvc_development)
if(TARGET rgvc_render)
  if(TARGET rgvc_render_gl)
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/render/include/
      DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT rgvc_development)
  else()
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/render/include/
      DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT rgvc_development PATTERN gl EXCLUDE)
  endif()
endif()

# One export set per part, so that the package finds a part's dependencies (libpng, OSMesa, GLFW) only
# when a consumer asks for that part. Targets of one set may use those of another (render -> dynamics).
install(TARGETS rgvc_grid rgvc_dynamics rgvc_rgvc EXPORT rgvcTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT rgvc_development
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT rgvc_development
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT rgvcTargets NAMESPACE rgvc:: DESTINATION ${RGVC_INSTALL_CMAKEDIR} COMPONENT rgvc_development)
set(RGVC_BUILT_COMPONENTS "")
foreach(part render render_gl)
  if(TARGET rgvc_${part})
    if(part STREQUAL "render_gl")
      set(component gl)
    else()
      set(component ${part})
    endif()
    list(APPEND RGVC_BUILT_COMPONENTS ${component})
    install(TARGETS rgvc_${part} EXPORT rgvc_${component}Targets
      ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT rgvc_development
      LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT rgvc_development
      INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
    install(EXPORT rgvc_${component}Targets NAMESPACE rgvc:: DESTINATION ${RGVC_INSTALL_CMAKEDIR}
      COMPONENT rgvc_development)
  endif()
endforeach()

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/rgvcConfig.cmake.in
  ${PROJECT_BINARY_DIR}/generated/rgvcConfig.cmake
  INSTALL_DESTINATION ${RGVC_INSTALL_CMAKEDIR})
# SameMinorVersion: before 1.0 a minor release may change the API (SemVer's 0.y rule), so
# find_package(rgvc 0.2) accepts 0.2.x only; at 1.0 this becomes SameMajorVersion.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/generated/rgvcConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/generated/rgvcConfig.cmake
              ${PROJECT_BINARY_DIR}/generated/rgvcConfigVersion.cmake
  DESTINATION ${RGVC_INSTALL_CMAKEDIR} COMPONENT rgvc_development)

# pkg-config (the core only): prefix relative to the .pc's own folder, so any install prefix works.
if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
  set(rgvc_pc_libdir "${CMAKE_INSTALL_LIBDIR}")
  set(rgvc_pc_up ".")
else()
  set(rgvc_pc_libdir "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
  file(RELATIVE_PATH rgvc_pc_up "/rgvc-root/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/rgvc-root")
  string(REGEX REPLACE "/$" "" rgvc_pc_up "${rgvc_pc_up}")
endif()
if(IS_ABSOLUTE "${CMAKE_INSTALL_INCLUDEDIR}")
  set(rgvc_pc_includedir "${CMAKE_INSTALL_INCLUDEDIR}")
else()
  set(rgvc_pc_includedir "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/rgvc.pc.in ${PROJECT_BINARY_DIR}/generated/rgvc.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/generated/rgvc.pc
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT rgvc_development)
