// Fuzz target: load_scene on a mesh file (scene/load.hpp), through the PLY header check and the
// importer child that runs Assimp (src/scene/isolated_import.hpp). The first byte picks the
// extension (OBJ, PLY, glTF, GLB, STL, Collada, OFF, 3DS, FBX); the rest is the file. load_scene
// must return a valid mesh or throw shprt::Error: a crash inside Assimp is the child's, and must
// come back as an error.
//
// The child is a fork of this fuzzer. So that a crash in it (Assimp's own: that is what the child
// is for) does not make libFuzzer's inherited handlers write crash-* files from the child,
// the child drops libFuzzer's death callback and fatal-signal handlers right after the fork; the
// sanitizers' own reports still happen in the child (ASAN_OPTIONS=log_path=... keeps them; see
// docs/fuzzing.md), the parent only sees "the importer crashed".
#include "fuzz_util.hpp"

#include "shprt/core/error.hpp"
#include "shprt/scene/load.hpp"

#include <pthread.h>
#include <sanitizer/common_interface_defs.h>
#include <signal.h>

#include <cmath>
#include <cstdlib>

namespace {

void in_child_after_fork() {
    __sanitizer_set_death_callback(nullptr);
    for (int sig : {SIGABRT, SIGBUS, SIGFPE, SIGILL, SIGINT, SIGTERM, SIGXFSZ, SIGUSR1, SIGUSR2})
        ::signal(sig, SIG_DFL);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    ::pthread_atfork(nullptr, nullptr, in_child_after_fork);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    static const char* const kExt[] = {".obj", ".ply", ".gltf", ".glb", ".stl",
                                       ".dae", ".off", ".3ds",  ".fbx"};
    const std::string path =
        shprt::fuzz::write_input(data + 1, size - 1, kExt[data[0] % std::size(kExt)]);
    try {
        const shprt::Mesh mesh = shprt::load_scene(path);
        const std::size_t V = mesh.positions.size();
        if (V == 0 || mesh.triangles.empty()) std::abort();  // an empty mesh is an error
        if (mesh.normals.size() != V || mesh.albedo.size() != V) std::abort();
        for (const auto& t : mesh.triangles)
            for (int c = 0; c < 3; ++c)
                if (t[c] >= V) std::abort();
        for (const auto& p : mesh.positions)
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
    } catch (const shprt::Error&) {
    }
    return 0;
}
