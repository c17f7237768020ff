// Shared by the fuzz targets: a scratch file that holds the current input, for the parsers that
// read paths (the .shprt reader, the scene loader, the light loaders).
#pragma once

#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace shprt::fuzz {

// A private folder under $TMPDIR (or /tmp), made once per process and removed at exit.
inline const std::string& scratch_dir() {
    static const std::string dir = [] {
        const char* tmp = std::getenv("TMPDIR");
        std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/shprt-fuzz-XXXXXX";
        if (!::mkdtemp(pattern.data())) std::abort();
        static std::string cleanup = pattern;
        std::atexit([] {
            std::string cmd = "rm -rf '" + cleanup + "'";
            (void)std::system(cmd.c_str());
        });
        return pattern;
    }();
    return dir;
}

// Writes `data` to scratch_dir()/input<ext> (the same path every time) and returns the path.
inline std::string write_input(const std::uint8_t* data, std::size_t size, const std::string& ext,
                               const std::string& stem = "input") {
    const std::string path = scratch_dir() + "/" + stem + ext;
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) std::abort();
    if (size && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
    return path;
}

}  // namespace shprt::fuzz
