# The test `consumer` (tests/CMakeLists.txt): installs the build into a fresh prefix, runs the
# installed `shprt --version`, and builds tests/consumer/main.cpp against the prefix twice, with
# find_package(shprt) and with pkg-config, running each program (it checks its own bake). Where
# the Python module is built, it checks the module went under the prefix too.
#   cmake -DBUILD=DIR -DSOURCE=DIR -DWORK=DIR -DCXX=COMPILER -DGENERATOR=NAME
#         [-DPYTHON_DIR=lib/python3.X/site-packages] -P check.cmake
foreach(var BUILD SOURCE WORK CXX GENERATOR)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "check.cmake: -D${var}=... is required")
    endif()
endforeach()
set(prefix ${WORK}/prefix)
file(REMOVE_RECURSE ${WORK})

set(RUN_NAME consumer)
include(${CMAKE_CURRENT_LIST_DIR}/run.cmake)

set(components cli dev)
if(PYTHON_DIR)
    list(APPEND components python)
endif()
foreach(component IN LISTS components)
    run(${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix} --component ${component})
endforeach()

run(${prefix}/bin/shprt --version)
if(NOT output MATCHES "^shprt [0-9]+\\.[0-9]+\\.[0-9]+ ")
    message(FATAL_ERROR "consumer: the installed shprt --version printed: ${output}")
endif()
if(PYTHON_DIR)
    file(GLOB module ${prefix}/${PYTHON_DIR}/shprt/_shprt*.so)
    if(NOT module OR NOT EXISTS ${prefix}/${PYTHON_DIR}/shprt/__init__.py)
        message(FATAL_ERROR "consumer: the Python module is not in ${prefix}/${PYTHON_DIR}/shprt")
    endif()
    # Typed (PEP 561): the extension's stubs and the marker that tells type checkers to read them.
    foreach(file _shprt.pyi py.typed)
        if(NOT EXISTS ${prefix}/${PYTHON_DIR}/shprt/${file})
            message(FATAL_ERROR "consumer: ${file} is not installed in ${prefix}/${PYTHON_DIR}/shprt")
        endif()
    endforeach()
endif()

# find_package(shprt) from the prefix; only the prefix is searched for it.
run(${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/cmake -G ${GENERATOR} -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run(${CMAKE_COMMAND} --build ${WORK}/cmake)
run(${WORK}/cmake/consumer)
message(STATUS "find_package: ${output}")

# pkg-config, as a Makefile would use it: the flags of shprt.pc and nothing else.
run(${CMAKE_COMMAND} -E env PKG_CONFIG_PATH=${prefix}/lib/pkgconfig pkg-config --cflags --libs shprt)
string(STRIP "${output}" flags)
separate_arguments(flags UNIX_COMMAND "${flags}")
run(${CXX} -std=c++20 ${SOURCE}/main.cpp ${flags} -o ${WORK}/pkg-config-consumer)
run(${WORK}/pkg-config-consumer)
message(STATUS "pkg-config: ${output}")
file(REMOVE_RECURSE ${WORK})
