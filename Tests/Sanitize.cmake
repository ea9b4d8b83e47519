# NRD_SANITIZE: the environment of the tests of this directory (ASan + UBSan + LSan), set once every
# test is declared (deferred to the end of Tests/CMakeLists.txt). The package test (it runs CMake)
# is left alone.
#   LD_PRELOAD      the sanitizer runtime first (GCC links it dynamically and must come first), then
#                   nrd_keep_vulkan_loaded (Tests/KeepVulkanLoaded.cpp), so that leaks inside the
#                   Vulkan driver and layers keep their module names;
#   LSAN_OPTIONS    Tests/lsan.supp: third-party Vulkan frames only;
#   ASAN_OPTIONS    initialization order and stack use after return on top of the defaults;
#   UBSAN_OPTIONS   stack traces (the build already aborts on the first report);
#   NRD_TEST_VALIDATION=0  no VK_LAYER_KHRONOS_validation (Tests/VulkanTestUtils.h): the Release job
#                   runs the same tests under it; here its per-object strings leak with stacks that
#                   end in libstdc++ (no frame pointers) and so escape lsan.supp.
add_library(nrd_keep_vulkan_loaded SHARED KeepVulkanLoaded.cpp)
target_link_libraries(nrd_keep_vulkan_loaded PRIVATE ${CMAKE_DL_LIBS})

function(nrd_sanitize_tests)
    set(preload "$<TARGET_FILE:nrd_keep_vulkan_loaded>")
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
        execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libasan.so
                        OUTPUT_VARIABLE asan OUTPUT_STRIP_TRAILING_WHITESPACE)
        set(preload "${asan}:${preload}")
    endif()
    get_property(tests DIRECTORY PROPERTY TESTS)
    foreach(test ${tests})
        get_test_property(${test} LABELS labels)
        if(labels STREQUAL "package")
            continue()
        endif()
        set_property(TEST ${test} APPEND PROPERTY ENVIRONMENT
            "LD_PRELOAD=${preload}"
            "LSAN_OPTIONS=suppressions=${CMAKE_CURRENT_SOURCE_DIR}/lsan.supp:print_suppressions=0"
            "ASAN_OPTIONS=check_initialization_order=1:strict_init_order=1:detect_stack_use_after_return=1"
            "UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1"
            "NRD_TEST_VALIDATION=0")
    endforeach()
endfunction()
cmake_language(DEFER CALL nrd_sanitize_tests)
