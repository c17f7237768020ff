// Private to src/scene: running a mesh importer in a child process, so that a crash inside it
// (Assimp 5.2.5's Collada reader dereferences a missing attribute, for one) becomes a clean
// shprt::Error naming the file instead of ending the whole program.
#pragma once

#include "shprt/scene/mesh.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace shprt::detail {

// What an importer hands over before the checks and normal recomputation that need no importer
// (those run in the caller's process, where logging is safe).
struct ImportedMesh {
    Mesh mesh;  // positions, normals, albedo, triangles, source_vertex (source is not carried)
    bool all_normals = true;          // every vertex had a usable normal in the file
    std::uint64_t skipped_faces = 0;  // points and lines left out
    std::uint8_t albedo_sources = 0;  // kAlbedo* bits: where the albedo came from
    // Every file the importer opened or tried (the scene, its materials, buffers, textures), as
    // paths relative to the working directory: the outputs may not be any of them.
    std::vector<std::string> files;
};
inline constexpr std::uint8_t kAlbedoVertexColours = 1, kAlbedoMaterial = 2, kAlbedoDefault = 4,
                              kAlbedoTexture = 8,
                              kAlbedoTextureUnreadable = 16;  // a texture named but not read

// Runs `work` in a child process made with fork() and returns its result, copied back through a
// pipe. The child may grow its address space by at most `memory_budget` bytes (RLIMIT_AS; not in
// sanitizer builds, whose shadow memory needs terabytes of address space): an allocation beyond
// it fails, and a std::bad_alloc that ends `work` becomes Error(out_of_memory) "PATH: the
// importer needed more than N GiB of memory ...". The child's stdout and stderr are /dev/null:
// nothing an importer prints reaches the terminal. A shprt::Error thrown in the child is thrown
// here with the same code and message (any other exception becomes Error(format) with its text). If
// the child ends without a result — killed by a signal (a segmentation fault in the importer, the
// OOM killer) or exiting early — throws Error(format) "PATH: the importer crashed reading this file
// (signal N, NAME) ...". `work` runs in a copy of a possibly multi-threaded process, so it must
// only compute: no locks another thread may hold (no logging, no TBB). Where fork() fails, `work`
// runs in this process. With `cpu_seconds` > 0 the child may use that much CPU time
// (RLIMIT_CPU, counted from the fork) and 3 times as much wall-clock time (alarm, for a child that
// waits rather than computes); past either, it is ended and this throws Error(format) "PATH: the
// importer took more than N s of CPU time reading this file ... set SHPRT_IMPORT_SECONDS to raise
// it". The child leaves no core file (RLIMIT_CORE 0).
ImportedMesh run_isolated_import(const std::string& path, std::uint64_t memory_budget,
                                 const std::function<ImportedMesh()>& work,
                                 unsigned cpu_seconds = 0);

}  // namespace shprt::detail
