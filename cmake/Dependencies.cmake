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

pkg_check_modules(OPENBLAS REQUIRED IMPORTED_TARGET openblas)
add_library(shprt_openblas INTERFACE)
target_link_libraries(shprt_openblas INTERFACE PkgConfig::OPENBLAS)

pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
add_library(shprt_stb INTERFACE)
target_link_libraries(shprt_stb INTERFACE PkgConfig::STB)

# The renderer (render/) always needs OpenGL through EGL and libepoxy: `shprt render` and the
# tests draw headless. SHPRT_BUILD_VIEWER adds only the window side: GLFW and Dear ImGui.
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)
pkg_check_modules(EPOXY REQUIRED IMPORTED_TARGET epoxy)
set(SHPRT_GL_LIBS PkgConfig::EPOXY OpenGL::EGL OpenGL::OpenGL)
set(SHPRT_HAS_VIEWER 0)
if(SHPRT_BUILD_VIEWER)
    set(SHPRT_HAS_VIEWER 1)
    find_package(glfw3 3.3 REQUIRED)
    pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
endif()
