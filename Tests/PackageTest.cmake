# Package and consumer tests (ctest label "package"), run in script mode:
#   cmake -DMODE=install -DBUILD_DIR=<build> -DSOURCE_DIR=<repo> -DWORK_DIR=<scratch> -DCONFIG=<cfg>
#         -DGENERATOR=<gen> -DCXX=<compiler> -P PackageTest.cmake
# MODE=install: installs the SDK, moves it (it must be relocatable), checks its file list against
#   Tests/PackageManifest.txt, that no file names the build or source tree and that static libraries
#   are deterministic archives, prints its size, then builds and runs two consumers with
#   find_package(NRD CONFIG REQUIRED):
#   (a) Examples/Vulkan: NRD::Core + NRD::Integration, denoises on the default Vulkan device and
#       checks against the known answer; (c) Examples/CoreOnly: NRD::Core only (static and shared),
#       walks the descriptions with its own executor; its compile and link commands, the headers it
#       includes and the libraries it loads must not involve Vulkan.
# MODE=subdirectory: (b) Tests/Consumers/Subdirectory takes the source tree with add_subdirectory
#   and builds and runs the same Vulkan example.
cmake_minimum_required(VERSION 3.22)

function(run_step what)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
    if(rc)
        message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
    endif()
    set(step_output "${out}${err}" PARENT_SCOPE)
endfunction()

# Configures and builds one consumer project; further arguments are extra -D cache entries.
function(build_consumer name source binary)
    set(args -S ${source} -B ${binary} -G ${GENERATOR} -DCMAKE_BUILD_TYPE=${CONFIG} -DCMAKE_CXX_COMPILER=${CXX} ${ARGN})
    run_step("${name}: configure" ${CMAKE_COMMAND} ${args})
    run_step("${name}: build" ${CMAKE_COMMAND} --build ${binary} --config ${CONFIG} --parallel 2 --verbose)
    set(step_output "${step_output}" PARENT_SCOPE)
endfunction()

function(run_consumer name executable)
    run_step("${name}: run" ${executable})
    message(STATUS "${name}: ${step_output}")
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})

if(MODE STREQUAL "subdirectory")
    build_consumer("add_subdirectory consumer" ${SOURCE_DIR}/Tests/Consumers/Subdirectory ${WORK_DIR}
                   -DNRD_SOURCE_DIR=${SOURCE_DIR})
    run_consumer("add_subdirectory consumer" ${WORK_DIR}/nrd_example_vulkan)
    return()
endif()

# Install, then move: nothing may depend on the install prefix.
set(stage ${WORK_DIR}/stage)
set(sdk ${WORK_DIR}/_NRD_SDK)
run_step("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${stage} --config ${CONFIG})
file(RENAME ${stage} ${sdk})

# The file list against the manifest.
file(GLOB_RECURSE files LIST_DIRECTORIES false RELATIVE ${sdk} ${sdk}/*)
list(SORT files)
file(STRINGS ${SOURCE_DIR}/Tests/PackageManifest.txt expected REGEX "^[^#]")
list(SORT expected)
set(bytes 0)
set(listing "")
foreach(f ${files})
    if(NOT IS_SYMLINK ${sdk}/${f})
        file(SIZE ${sdk}/${f} size)
        math(EXPR bytes "${bytes} + ${size}")
    endif()
    string(APPEND listing "${f}\n")
endforeach()
file(STRINGS ${SOURCE_DIR}/Tests/PackageManifest.txt header REGEX "^#") # (No ';' in these comments.)
list(JOIN header "\n" header)
file(WRITE ${WORK_DIR}/PackageManifest.txt "${header}\n${listing}")
if(NOT files STREQUAL expected)
    set(added ${files})
    list(REMOVE_ITEM added ${expected})
    set(missing ${expected})
    list(REMOVE_ITEM missing ${files})
    string(REPLACE ";" "\n  " added "${added}")
    string(REPLACE ";" "\n  " missing "${missing}")
    message(FATAL_ERROR "The installed SDK differs from Tests/PackageManifest.txt.\n"
        "New files:\n  ${added}\nMissing files:\n  ${missing}\n"
        "If the change is intended, take the new list:\n"
        "  cp ${WORK_DIR}/PackageManifest.txt ${SOURCE_DIR}/Tests/PackageManifest.txt")
endif()
list(LENGTH files count)
math(EXPR kib "${bytes} / 1024")
message(STATUS "package: ${count} files, ${bytes} bytes (${kib} KiB)")

# Relocatable: no file names the trees it was made from.
foreach(f ${files})
    foreach(tree ${BUILD_DIR} ${SOURCE_DIR} ${stage})
        string(REGEX REPLACE "([][+.*()^$?|\\])" "\\\\\\1" tree_regex "${tree}")
        file(STRINGS ${sdk}/${f} hits LIMIT_COUNT 1 REGEX "${tree_regex}")
        if(hits)
            message(FATAL_ERROR "${f} names ${tree}: the package is not relocatable (${hits})")
        endif()
    endforeach()
endforeach()

# GLM is a private, build-time dependency of the core: no installed CMake file may ask for it.
foreach(f ${files})
    if(f MATCHES "\\.cmake$")
        file(STRINGS ${sdk}/${f} hits LIMIT_COUNT 1 REGEX "glm")
        if(hits)
            message(FATAL_ERROR "${f} names GLM, a private build-time dependency of the core (${hits})")
        endif()
    endif()
endforeach()

# Reproducible archives: every member of a static library carries time 0 (deterministic mode), so
# two builds of the same sources give the same bytes. Each 60-byte member header holds its time at
# bytes 16..27, in decimal ASCII padded with spaces.
foreach(f ${files})
    if(NOT f MATCHES "\\.a$")
        continue()
    endif()
    file(SIZE ${sdk}/${f} size)
    set(offset 8) # After "!<arch>\n".
    while(offset LESS size)
        math(EXPR time_offset "${offset} + 16")
        file(READ ${sdk}/${f} header OFFSET ${offset} LIMIT 60)
        file(READ ${sdk}/${f} member_time OFFSET ${time_offset} LIMIT 12 HEX)
        # "0" or, for the long-name table, blank.
        if(NOT member_time MATCHES "^(30|20)2020202020202020202020$")
            message(FATAL_ERROR "${f}: archive member at byte ${offset} has a time stamp (${member_time}); "
                                "archives must be written in deterministic mode (ar D)")
        endif()
        string(SUBSTRING "${header}" 48 10 member_size)
        string(STRIP "${member_size}" member_size)
        math(EXPR offset "${offset} + 60 + ${member_size} + (${member_size} % 2)")
    endwhile()
endforeach()

# (a) find_package with both components; denoises on the default Vulkan device.
build_consumer("find_package consumer" ${sdk}/Examples/Vulkan ${WORK_DIR}/vulkan -DCMAKE_PREFIX_PATH=${sdk})
run_consumer("find_package consumer" ${WORK_DIR}/vulkan/nrd_example_vulkan)

# (c) core only: -H lists every header the compiler opens; the verbose build shows every command.
build_consumer("core-only consumer" ${sdk}/Examples/CoreOnly ${WORK_DIR}/core -DCMAKE_PREFIX_PATH=${sdk} -DCMAKE_CXX_FLAGS=-H)
string(TOLOWER "${step_output}" build_log)
if(NOT build_log MATCHES "nrd\\.h")
    message(FATAL_ERROR "core-only consumer: the build log lists no included header; cannot check it:\n${step_output}")
endif()
if(build_log MATCHES "vulkan")
    message(FATAL_ERROR "core-only consumer: Vulkan appears in its build (include path, headers or link line):\n${step_output}")
endif()
if(build_log MATCHES "glm")
    message(FATAL_ERROR "core-only consumer: GLM appears in its build (the core uses it privately):\n${step_output}")
endif()
foreach(exe nrd_example_core nrd_example_core_shared)
    file(GET_RUNTIME_DEPENDENCIES EXECUTABLES ${WORK_DIR}/core/${exe} RESOLVED_DEPENDENCIES_VAR resolved
         UNRESOLVED_DEPENDENCIES_VAR unresolved)
    string(TOLOWER "${resolved};${unresolved}" libraries)
    if(libraries MATCHES "vulkan")
        message(FATAL_ERROR "core-only consumer: ${exe} loads Vulkan: ${resolved} ${unresolved}")
    endif()
    run_consumer("core-only consumer (${exe})" ${WORK_DIR}/core/${exe})
endforeach()
if(NOT libraries MATCHES "libnrd\\.so")
    message(FATAL_ERROR "core-only consumer: nrd_example_core_shared does not load libNRD.so: ${resolved}")
endif()
