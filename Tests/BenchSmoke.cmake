# cmake -DBENCH=<nrd-bench> -DWORK_DIR=<dir> -DPRESETS=<file.json> -P BenchSmoke.cmake
# A short lavapipe run of nrd-bench over the shadow methods and REFERENCE (one setting each, two
# for TILED_SHADOW; REBLUR_DIFFUSE_SPECULAR fails in the method runner on lavapipe today),
# then checks its outputs: the JSON report against the schema and the bandwidth bound
# (nrd-bench --validate), the Markdown table, and one PNG plot per method.
file(REMOVE_RECURSE ${WORK_DIR})
execute_process(
    COMMAND ${BENCH} --methods SIGMA_SHADOW,SIGMA_SHADOW_TRANSLUCENCY,REFERENCE,TILED_SHADOW --sizes 64x64 --error-size 64x64 --scene static --frames 4 --truth-spp 8 --timed-frames 8
            --warmup-frames 4 --frames-per-submission 4 --copy-mib 8 --budget-ms 1000 --presets ${PRESETS}
            --cache ${WORK_DIR}/cache --out ${WORK_DIR} --quiet
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
message(STATUS "nrd-bench smoke: ${results_num} settings, report valid")
