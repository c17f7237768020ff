# run(COMMAND...): runs a command of the package tests (check.cmake, deb.cmake); on failure stops
# with the command, its status and its output, prefixed with ${RUN_NAME}; else leaves its output
# in `output`.
function(run)
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
    if(NOT status EQUAL 0)
        message(FATAL_ERROR "${RUN_NAME}: `${ARGN}` failed (${status}):\n${out}")
    endif()
    set(output "${out}" PARENT_SCOPE)
endfunction()
