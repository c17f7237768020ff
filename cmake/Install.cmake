# `cmake --install build --prefix P` (README, "Install"): the command line, the headers, the static
# libraries as the CMake package `shprt` (find_package(shprt) gives shprt::shprt, the umbrella,
# shprt::baker, everything but the renderer, and one target per area: shprt::core, shprt::bake,
# ...), a pkg-config file shprt.pc, and the Python module when it is built (python/). Checked by
# the test `consumer` (tests/consumer/), which installs into a temporary prefix and builds a
# program against it both ways.
include(CMakePackageConfigHelpers)

set(shprt_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/shprt)

# The command line: `shprt` in bin/ and the library it loads in lib/shprt/, a private folder (no
# program links it). The launcher finds it there by the path from bin/ to lib/ (tools/launcher.cpp).
install(TARGETS shprt_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT cli)
install(TARGETS shprt_cli_library LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/shprt COMPONENT cli)

# The libraries: every area built, the two umbrellas, and the interface targets they name (the
# private ones only as link-only items).
get_property(shprt_installed_areas GLOBAL PROPERTY shprt_areas)
set(shprt_exported shprt shprt_baker shprt_warnings shprt_sanitize shprt_fuzz_coverage
                   shprt_openblas shprt_stb)
foreach(area IN LISTS shprt_installed_areas)
    list(APPEND shprt_exported shprt_${area})
    install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/shprt/${area}
            DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/shprt COMPONENT dev)
endforeach()
if(TARGET shprt_cuda)
    list(APPEND shprt_exported shprt_cuda)
endif()
install(TARGETS ${shprt_exported} EXPORT shprtTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
install(FILES ${PROJECT_BINARY_DIR}/generated/shprt/config.hpp
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/shprt COMPONENT dev)
install(EXPORT shprtTargets NAMESPACE shprt:: DESTINATION ${shprt_cmake_dir} COMPONENT dev)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/shprtConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/shprtConfig.cmake
                              INSTALL_DESTINATION ${shprt_cmake_dir})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/shprtConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/shprtConfig.cmake ${PROJECT_BINARY_DIR}/shprtConfigVersion.cmake
        DESTINATION ${shprt_cmake_dir} COMPONENT dev)

# shprt.pc: the static libraries, most dependent first, then what they link. Relocatable: the
# prefix is found from the .pc file's own folder, so `--prefix P` at install time holds.
set(shprt_pc_libs "")
foreach(area render dist bake shade cuda light io transfer trace scene sh core)
    if(TARGET shprt_${area})
        string(APPEND shprt_pc_libs " -lshprt_${area}")
    endif()
endforeach()
set(shprt_pc_requires "fmt tbb assimp zlib openblas stb")
string(APPEND shprt_pc_libs " -lembree3 -ltinyexr")
if(SHPRT_HAS_RENDER)
    string(APPEND shprt_pc_requires " epoxy egl opengl")
endif()
if(TARGET shprt_cuda)
    string(APPEND shprt_pc_libs " -L${CUDAToolkit_LIBRARY_DIR} -lcudart_static -lrt")
endif()
if(SHPRT_HAS_MPI)
    foreach(lib IN LISTS MPI_C_LIBRARIES)
        string(APPEND shprt_pc_libs " ${lib}")
    endforeach()
endif()
foreach(lib IN LISTS CMAKE_DL_LIBS)
    string(APPEND shprt_pc_libs " -l${lib}")
endforeach()
string(APPEND shprt_pc_libs " -pthread")
# A sanitizer build's libraries need the sanitizer's runtime in the program that links them.
set(shprt_pc_cflags "")
if(SHPRT_SANITIZE)
    set(shprt_pc_cflags " -fsanitize=address,undefined")
elseif(SHPRT_TSAN)
    set(shprt_pc_cflags " -fsanitize=thread")
endif()
string(APPEND shprt_pc_libs "${shprt_pc_cflags}")
file(RELATIVE_PATH shprt_pc_prefix ${CMAKE_INSTALL_FULL_LIBDIR}/pkgconfig ${CMAKE_INSTALL_PREFIX})
string(REGEX REPLACE "/$" "" shprt_pc_prefix "${shprt_pc_prefix}")
configure_file(${PROJECT_SOURCE_DIR}/cmake/shprt.pc.in ${PROJECT_BINARY_DIR}/shprt.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/shprt.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig
        COMPONENT dev)

# The test `consumer` (tests/consumer/check.cmake): the install into a temporary prefix, and a
# program built against it with find_package and with pkg-config. Here, after python/, so that it
# knows where the module installs. About 10 s (two compiles of one file).
if(SHPRT_BUILD_TESTS)
    set(shprt_consumer_python "")
    get_property(shprt_python_dir GLOBAL PROPERTY shprt_python_install_dir)
    if(TARGET shprt_python AND NOT IS_ABSOLUTE "${shprt_python_dir}")
        set(shprt_consumer_python -DPYTHON_DIR=${shprt_python_dir})
    endif()
    add_test(NAME consumer
             COMMAND ${CMAKE_COMMAND} -DBUILD=${PROJECT_BINARY_DIR}
                     -DSOURCE=${PROJECT_SOURCE_DIR}/tests/consumer
                     -DWORK=${PROJECT_BINARY_DIR}/consumer-test -DCXX=${CMAKE_CXX_COMPILER}
                     -DGENERATOR=${CMAKE_GENERATOR} ${shprt_consumer_python}
                     -P ${PROJECT_SOURCE_DIR}/tests/consumer/check.cmake)
    set_tests_properties(consumer PROPERTIES LABELS package COST 20 RESOURCE_LOCK shprt_install)
    # The same project taking shprt in with add_subdirectory: configured and generated only (about
    # 2 s; building it builds the whole library again, minutes). It catches what broke
    # add_subdirectory before (paths from CMAKE_SOURCE_DIR: "No SOURCES given to target").
    add_test(NAME consumer_subdirectory
             COMMAND ${CMAKE_COMMAND} -S ${PROJECT_SOURCE_DIR}/tests/consumer
                     -B ${PROJECT_BINARY_DIR}/consumer-subdirectory -G ${CMAKE_GENERATOR}
                     -DCMAKE_CXX_COMPILER=${CMAKE_CXX_COMPILER} -DCMAKE_C_COMPILER=${CMAKE_C_COMPILER}
                     -DSHPRT_SOURCE_DIR=${PROJECT_SOURCE_DIR} -DSHPRT_CUDA=OFF)
    set_tests_properties(consumer_subdirectory PROPERTIES LABELS package)
endif()
