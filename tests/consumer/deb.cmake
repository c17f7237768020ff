# The test `deb` (cmake/Package.cmake): the command line's Debian package made by CPack in a
# fresh folder, its control data read back (dpkg-deb -I: name, version, the library packages
# dpkg-shlibdeps found), its files listed, and `shprt --version` run from the package unpacked
# into a folder (no root needed: the launcher finds its library relative to itself).
#   cmake -DBUILD=DIR -DWORK=DIR -DVERSION=X.Y.Z -P deb.cmake
foreach(var BUILD WORK VERSION)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "deb.cmake: -D${var}=... is required")
    endif()
endforeach()
file(REMOVE_RECURSE ${WORK})

set(RUN_NAME deb)
include(${CMAKE_CURRENT_LIST_DIR}/run.cmake)
function(expect text regex what)
    if(NOT text MATCHES "${regex}")
        message(FATAL_ERROR "deb: ${what} (no match for '${regex}') in:\n${text}")
    endif()
endfunction()

run(cpack -G DEB --config ${BUILD}/CPackConfig.cmake -B ${WORK} -D CPACK_COMPONENTS_ALL=cli)
file(GLOB deb ${WORK}/shprt_*.deb)
list(LENGTH deb count)
if(NOT count EQUAL 1)
    message(FATAL_ERROR "deb: expected one shprt_*.deb in ${WORK}, found: ${deb}")
endif()

run(dpkg-deb -I ${deb})
expect("${output}" "\n Package: shprt\n" "the package's name")
expect("${output}" "\n Version: ${VERSION}\n" "the project's version")
expect("${output}" "\n Depends: [^\n]*libassimp5[^\n]*\n" "the Assimp library in Depends")
expect("${output}" "\n Depends: [^\n]*libembree3-3[^\n]*\n" "the Embree library in Depends")
expect("${output}" "\n Depends: [^\n]*libtbb[^\n]*\n" "the oneTBB library in Depends")
run(dpkg-deb -c ${deb})
expect("${output}" " \\./usr/bin/shprt\n" "the program")
expect("${output}" " \\./usr/lib/shprt/libshprt_cli\\.so\n" "the library it loads")

run(dpkg-deb -x ${deb} ${WORK}/root)
run(${WORK}/root/usr/bin/shprt --version)
expect("${output}" "^shprt ${VERSION} " "`shprt --version` from the unpacked package")
file(REMOVE_RECURSE ${WORK})
