# Install rules: `cmake --install <build> --prefix _NRD_SDK` produces the packaged SDK, consumable
# with find_package(NRD) (targets NRD::Core and, when built, NRD::Integration).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(NRD_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/NRD)

install(TARGETS nrd_core EXPORT NRDTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(FILES Include/NRD.h Include/NRDDescs.h Include/NRDSettings.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# Public shader API (front end / back end helpers) for the application's own shaders.
install(FILES Shaders/Include/NRD.glsl DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

set(NRD_WITH_INTEGRATION OFF)
if(TARGET nrd_integration)
    set(NRD_WITH_INTEGRATION ON)
    install(TARGETS nrd_integration EXPORT NRDTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
    file(GLOB _nrd_integration_headers ${PROJECT_SOURCE_DIR}/Integration/*.h)
    install(FILES ${_nrd_integration_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
endif()

install(EXPORT NRDTargets NAMESPACE NRD:: DESTINATION ${NRD_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/_NRD_SDK-template/NRDConfig.cmake.in
    ${PROJECT_BINARY_DIR}/NRDConfig.cmake INSTALL_DESTINATION ${NRD_INSTALL_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/NRDConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/NRDConfig.cmake ${PROJECT_BINARY_DIR}/NRDConfigVersion.cmake
    DESTINATION ${NRD_INSTALL_CMAKEDIR})
install(FILES ${PROJECT_SOURCE_DIR}/_NRD_SDK-template/README.md DESTINATION .)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/_NRD_SDK-template/Example DESTINATION .)
