// The study's options from what `shprt bench paper` was given (paper_study.hpp).
#include "paper/paper_study.hpp"

#include "shprt/core/error.hpp"
#include "shprt/scene/room.hpp"

namespace shprt::paper {

Options options_from(OptionChoice a) {
    Options o = a.options;
    SHPRT_CHECK(o.device == "cpu" || o.device == "cuda" || o.device == "both" || o.device == "auto",
                invalid_argument, "--device '{}': expected cpu, cuda, both or auto", o.device);
    o.sampler = parse_sampler_kind(a.sampler);
    if (o.quick) {
        // A tiny run (tests, smoke checks): a small room and few samples, unless given.
        if (a.samples == 4096) a.samples = 256;
        if (a.gt_samples == 16384) a.gt_samples = 256;
        if (a.triangles == 20000) a.triangles = 2000;
        if (a.frames == 30) a.frames = 3;
    }
    SHPRT_CHECK(a.samples >= 1 && a.samples <= (1 << 24), invalid_argument,
                "--samples {}: must be in [1, 2^24]", a.samples);
    SHPRT_CHECK(a.gt_samples >= 4 && a.gt_samples <= (1 << 20), invalid_argument,
                "--gt-samples {}: must be in [4, 2^20]", a.gt_samples);
    SHPRT_CHECK(a.triangles >= static_cast<long long>(kRoomMinTriangles) &&
                    a.triangles <= static_cast<long long>(kRoomMaxTriangles),
                invalid_argument, "--triangles {}: must be in [{}, {}]", a.triangles,
                kRoomMinTriangles, kRoomMaxTriangles);
    SHPRT_CHECK(a.frames >= 1 && a.frames <= 100000, invalid_argument,
                "--frames {}: must be in [1, 100000]", a.frames);
    SHPRT_CHECK(a.threads >= 0 && a.threads <= 4096, invalid_argument,
                "--threads {}: must be ≥ 0 (0 = all)", a.threads);
    SHPRT_CHECK(!o.out_dir.empty(), invalid_argument, "-o: empty output directory");
    o.samples = static_cast<std::uint32_t>(a.samples);
    o.gt_samples = static_cast<std::uint32_t>(a.gt_samples);
    o.triangles = static_cast<std::size_t>(a.triangles);
    o.frames = static_cast<int>(a.frames);
    o.threads = static_cast<int>(a.threads);
    o.study = !a.no_study;
    o.images = !a.no_images;
    return o;
}

}  // namespace shprt::paper
