// Fuzz target: the .shprt reader (io/shprt_file.hpp). Any input either reads into a file whose
// arrays agree with its metadata, or is refused with shprt::Error; anything else (a sanitizer
// report, another exception) is a finding. The target turns the reader's checksums advisory
// (src/io/fuzzing.hpp), so mutations reach the checks behind the CRCs.
#include "fuzz_util.hpp"
#include "io/fuzzing.hpp"

#include "shprt/core/error.hpp"
#include "shprt/io/shprt_file.hpp"

#include <cstdlib>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    shprt::io_fuzzing::set_checksums_advisory(true);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = shprt::fuzz::write_input(data, size, ".shprt");
    for (const bool part : {false, true}) {
        try {
            const shprt::ShprtFile f =
                part ? shprt::read_shprt_part(path) : shprt::read_shprt(path);
            // What the reader promises: arrays sized as the metadata says.
            const std::size_t V = f.mesh.positions.size();
            if (f.mesh.normals.size() != V || f.mesh.albedo.size() != V) std::abort();
            for (const auto& t : f.mesh.triangles)
                for (int c = 0; c < 3; ++c)
                    if (t[c] >= V) std::abort();
            (void)shprt::shprt_summary(f);
        } catch (const shprt::Error&) {
        }
    }
    return 0;
}
