# `cpack -G DEB` in the build folder (README, "Install"): Debian packages of what
# cmake/Install.cmake installs, one per component, under /usr:
#   shprt          the command line (bin/shprt, lib/shprt/libshprt_cli.so); the libraries it loads
#                  are found by dpkg-shlibdeps (dpkg-dev) and declared in Depends
#   shprt-dev      the headers, static libraries, CMake package and shprt.pc; Depends on the
#                  Debian -dev packages whose libraries the static ones link
#   python3-shprt  the module (lib/python3.X/dist-packages/shprt), when it is built
# Checked by the test `deb` (label package): the control data (dpkg-deb -I) and
# `shprt --version` run from the unpacked package.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME shprt)
set(CPACK_PACKAGE_CONTACT "shprt developers")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "precomputed radiance transfer in spherical harmonics: baker, library and command line")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL cli dev)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_CLI_PACKAGE_NAME shprt)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME shprt-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
set(shprt_deb_dev_depends
    "libfmt-dev, libtbb-dev, libembree-dev, libassimp-dev, libtinyexr-dev, libopenblas-dev, "
    "libstb-dev, nlohmann-json3-dev, libeigen3-dev, zlib1g-dev, pkg-config")
if(SHPRT_HAS_RENDER)
    string(APPEND shprt_deb_dev_depends ", libepoxy-dev, libegl-dev, libgl-dev")
endif()
if(SHPRT_HAS_MPI)
    string(APPEND shprt_deb_dev_depends ", libopenmpi-dev")
endif()
string(CONCAT CPACK_DEBIAN_DEV_PACKAGE_DEPENDS ${shprt_deb_dev_depends})
if(TARGET shprt_python)
    list(APPEND CPACK_COMPONENTS_ALL python)
    set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-shprt)
    set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
    set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS "python3-numpy")
endif()
include(CPack)

if(SHPRT_BUILD_TESTS)
    add_test(NAME deb COMMAND ${CMAKE_COMMAND} -DBUILD=${PROJECT_BINARY_DIR}
                              -DWORK=${PROJECT_BINARY_DIR}/deb-test -DVERSION=${PROJECT_VERSION}
                              -P ${PROJECT_SOURCE_DIR}/tests/consumer/deb.cmake)
    # RESOURCE_LOCK: it and `consumer` both run the build folder's install scripts; one at a time.
    set_tests_properties(deb PROPERTIES LABELS package RESOURCE_LOCK shprt_install)
endif()
