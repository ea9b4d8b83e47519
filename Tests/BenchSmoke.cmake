# cmake -DBENCH=<nrd-bench> -DWORK_DIR=<dir> -DPRESETS=<file.json> -P BenchSmoke.cmake
# A short lavapipe run of nrd-bench over every method of the library's list (each at its default
# settings, two for TILED_SHADOW: PRESETS), at a tiny size, two error runs at a time, with
# nrd-sample's one-frame-per-submission pattern, then checks its outputs: the JSON report against
# the schema and the bandwidth bound (nrd-bench --validate), the Markdown table, and one PNG plot
# per method.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(
    COMMAND ${BENCH} --sizes 16x16 --error-size 16x16 --error-jobs 2 --scene static --frames 3 --truth-spp 4
            --timed-frames 2 --warmup-frames 1 --frames-per-submission 2 --isolated-idle-ms 1 --copy-mib 1
            --budget-ms 1000 --presets ${PRESETS} --cache ${WORK_DIR}/cache --out ${WORK_DIR} --quiet
    RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE errors)
if(NOT result EQUAL 0)
    message(FATAL_ERROR "nrd-bench failed (${result}):\n${output}\n${errors}")
endif()
if(errors MATCHES "warning")
    message(FATAL_ERROR "nrd-bench reported:\n${errors}")
endif()
execute_process(COMMAND ${BENCH} --validate ${WORK_DIR}/bench.json RESULT_VARIABLE result ERROR_VARIABLE errors)
if(NOT result EQUAL 0)
    message(FATAL_ERROR "report rejected: ${errors}")
endif()
file(READ ${WORK_DIR}/bench.md markdown)
if(NOT markdown MATCHES "\\| TILED_SHADOW \\| atrous-1")
    message(FATAL_ERROR "bench.md lacks the TILED_SHADOW rows:\n${markdown}")
endif()
# Every method nrd-bench --list-methods names has its row.
execute_process(COMMAND ${BENCH} --list-methods RESULT_VARIABLE result OUTPUT_VARIABLE methods)
string(REPLACE "\n" ";" methods "${methods}")
list(FILTER methods EXCLUDE REGEX "^$")
list(LENGTH methods methods_num)
if(NOT result EQUAL 0 OR methods_num LESS 5)
    message(FATAL_ERROR "nrd-bench --list-methods: ${result}, '${methods}'")
endif()
foreach(method IN LISTS methods)
    if(NOT markdown MATCHES "\\| ${method} \\| default")
        message(FATAL_ERROR "bench.md lacks ${method}:\n${markdown}")
    endif()
endforeach()
# One plot per method of the report, each a PNG.
file(READ ${WORK_DIR}/bench.json report)
string(JSON results_num LENGTH "${report}" results)
math(EXPR last "${results_num} - 1")
foreach(i RANGE ${last})
    string(JSON method GET "${report}" results ${i} method)
    set(png ${WORK_DIR}/${method}.png)
    if(NOT EXISTS ${png})
        message(FATAL_ERROR "no plot ${png}")
    endif()
    file(READ ${png} signature LIMIT 8 HEX)
    if(NOT signature STREQUAL "89504e470d0a1a0a")
        message(FATAL_ERROR "${png} is not a PNG")
    endif()
endforeach()
message(STATUS "nrd-bench smoke: ${methods_num} methods, ${results_num} settings, report valid")
