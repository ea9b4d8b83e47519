# Install rules of the packaged SDK. `cmake --build build --target nrd_sdk` (or
# `cmake --install build --prefix <dir>`) produces _NRD_SDK:
#   include/             public C++ headers (Include/*.h, Integration/*.h) and shader helpers
#                        (Shaders/Include/NRD*.glsl, NRD*.hlsli)
#   lib/                 libNRD.a (NRD::Core), libNRD.so (NRD::CoreShared), libNRDIntegration.a
#   lib/cmake/NRD/       find_package(NRD) files, relocatable; components Core and Integration
#   README.md, INTEGRATION.md, CHANGELOG.md, LICENSE, Examples/ (Vulkan, CoreOnly)
# New public headers and shader helpers are picked up by the globs below; Tests/PackageManifest.txt
# lists the expected files (the nrd_package_test failure says how to update it).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(NRD_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/NRD)

install(TARGETS nrd_core nrd_core_shared EXPORT NRDCoreTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
file(GLOB _nrd_public_headers CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/Include/*.h)
install(FILES ${_nrd_public_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# Public shader API (front end / back end helpers) for the application's own shaders, GLSL and HLSL.
# The other files of Shaders/Include are the passes' internals.
file(GLOB _nrd_shader_helpers CONFIGURE_DEPENDS
    ${PROJECT_SOURCE_DIR}/Shaders/Include/NRD*.glsl ${PROJECT_SOURCE_DIR}/Shaders/Include/NRD*.hlsli)
install(FILES ${_nrd_shader_helpers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT NRDCoreTargets NAMESPACE NRD:: DESTINATION ${NRD_INSTALL_CMAKEDIR})

set(NRD_WITH_INTEGRATION OFF)
if(TARGET nrd_integration)
    set(NRD_WITH_INTEGRATION ON)
    install(TARGETS nrd_integration EXPORT NRDIntegrationTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
    file(GLOB _nrd_integration_headers CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/Integration/*.h)
    install(FILES ${_nrd_integration_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
    install(EXPORT NRDIntegrationTargets NAMESPACE NRD:: DESTINATION ${NRD_INSTALL_CMAKEDIR})
endif()

configure_package_config_file(${PROJECT_SOURCE_DIR}/_NRD_SDK-template/NRDConfig.cmake.in
    ${PROJECT_BINARY_DIR}/NRDConfig.cmake INSTALL_DESTINATION ${NRD_INSTALL_CMAKEDIR} PATH_VARS CMAKE_INSTALL_INCLUDEDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/NRDConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/NRDConfig.cmake ${PROJECT_BINARY_DIR}/NRDConfigVersion.cmake
    DESTINATION ${NRD_INSTALL_CMAKEDIR})

install(FILES ${PROJECT_SOURCE_DIR}/_NRD_SDK-template/README.md ${PROJECT_SOURCE_DIR}/LICENSE
    ${PROJECT_SOURCE_DIR}/CHANGELOG.md DESTINATION .)
install(FILES ${PROJECT_SOURCE_DIR}/Integration/README.md DESTINATION . RENAME INTEGRATION.md)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/_NRD_SDK-template/Examples DESTINATION .)

# `cmake --build build --target nrd_sdk`: a fresh build/_NRD_SDK (stale files removed first).
set(NRD_SDK_DIR ${PROJECT_BINARY_DIR}/_NRD_SDK CACHE PATH "Where the nrd_sdk target installs the packaged SDK")
add_custom_target(nrd_sdk
    COMMAND ${CMAKE_COMMAND} -E rm -rf ${NRD_SDK_DIR}
    COMMAND ${CMAKE_COMMAND} --install ${PROJECT_BINARY_DIR} --prefix ${NRD_SDK_DIR} --config $<CONFIG>
    COMMENT "Packaging the SDK into ${NRD_SDK_DIR}"
    VERBATIM)
add_dependencies(nrd_sdk nrd_core nrd_core_shared)
if(TARGET nrd_integration)
    add_dependencies(nrd_sdk nrd_integration)
endif()
