# Every dependency is a Debian package (scripts/setup installs them all).
find_package(Threads REQUIRED)
find_package(PkgConfig REQUIRED)
find_package(fmt REQUIRED)
find_package(spdlog REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(ZLIB REQUIRED)
find_package(TBB REQUIRED)
find_package(embree 3 REQUIRED)
find_package(assimp REQUIRED)
find_package(tinyexr REQUIRED)
# Eigen 3 (header-only): the sparse transport operator of interreflected transfer (src/bake), the
# conformal UV charts (src/scene/uv_atlas.cpp).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)

pkg_check_modules(OPENBLAS REQUIRED IMPORTED_TARGET openblas)
add_library(shprt_openblas INTERFACE)
target_link_libraries(shprt_openblas INTERFACE PkgConfig::OPENBLAS)

pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
add_library(shprt_stb INTERFACE)
target_link_libraries(shprt_stb INTERFACE PkgConfig::STB)

# The renderer (render/) needs OpenGL through EGL and libepoxy (`shprt render` and the tests draw
# headless); SHPRT_RENDER=AUTO builds it when they are found, OFF leaves every GL package out (the
# baker, shprt::baker, never needs one). The viewer adds the window side: GLFW and Dear ImGui.
set(SHPRT_HAS_RENDER 0)
if(NOT SHPRT_RENDER STREQUAL "OFF")
    set(shprt_gl_required "")
    if(SHPRT_RENDER STREQUAL "ON")
        set(shprt_gl_required REQUIRED)
    endif()
    find_package(OpenGL ${shprt_gl_required} COMPONENTS OpenGL EGL)
    pkg_check_modules(EPOXY ${shprt_gl_required} IMPORTED_TARGET epoxy)
    # OPENGL_FOUND too: without libOpenGL.so (libopengl-dev) FindOpenGL still reports the
    # components it found but makes no imported targets, and the render area could not link.
    if(OPENGL_FOUND AND OpenGL_OpenGL_FOUND AND OpenGL_EGL_FOUND AND EPOXY_FOUND)
        set(SHPRT_HAS_RENDER 1)
        set(SHPRT_GL_LIBS PkgConfig::EPOXY OpenGL::EGL OpenGL::OpenGL)
    endif()
endif()
set(SHPRT_HAS_VIEWER 0)
if(SHPRT_BUILD_VIEWER AND SHPRT_HAS_RENDER)
    set(SHPRT_HAS_VIEWER 1)
    find_package(glfw3 3.3 REQUIRED)
    pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
endif()
if(SHPRT_HAS_RENDER)
    message(STATUS "shprt: renderer: OpenGL through EGL (viewer: ${SHPRT_HAS_VIEWER})")
else()
    message(STATUS "shprt: renderer: off (SHPRT_RENDER=${SHPRT_RENDER}): the baker only")
endif()

# MPI (Open MPI from Debian's libopenmpi-dev) for `mpirun -np P shprt bake` (dist/): SHPRT_MPI=AUTO
# builds it when found, ON requires it, OFF leaves it out; everything else works without it.
set(SHPRT_HAS_MPI 0)
if(NOT SHPRT_MPI STREQUAL "OFF")
    set(shprt_mpi_required "")
    if(SHPRT_MPI STREQUAL "ON")
        set(shprt_mpi_required REQUIRED)
    endif()
    find_package(MPI ${shprt_mpi_required} COMPONENTS C)
    if(MPI_C_FOUND)
        set(SHPRT_HAS_MPI 1)
        message(STATUS "shprt: MPI ${MPI_C_VERSION} (${MPI_C_LIB_NAMES}): `mpirun shprt bake` shares a bake between ranks")
    endif()
endif()
if(NOT SHPRT_HAS_MPI)
    message(STATUS "shprt: MPI: off (SHPRT_MPI=${SHPRT_MPI}): shard with --shard I/N and shprt merge")
endif()
