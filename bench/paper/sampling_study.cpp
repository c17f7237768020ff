// Sampling-study stage of the paper study (sampling_study.hpp).
#include "paper/sampling_study.hpp"

#include "paper/bake_sweep.hpp"
#include "paper/quality.hpp"

#include "shprt/bake/bake.hpp"
#include "shprt/light/light.hpp"
#include "shprt/trace/tracer.hpp"

#include <fmt/format.h>

#include <memory>
#include <vector>

namespace shprt::paper {

void run_sampling_study(const Mesh& mesh, const Lights& lights, const Truth& truth,
                        const Options& o, Results& res, const StageLog& stage) {
    const std::vector<std::uint32_t> S_list = o.quick
                                                  ? std::vector<std::uint32_t>{64, 256}
                                                  : std::vector<std::uint32_t>{64, 256, 1024, 4096};
    res.study_K = o.quick ? 16 : 64;
    res.study_reference_samples = 4 * S_list.back();
    const ShLight sky = make_light(lights.sky_specs, res.study_K);
    const ShLight sun = make_light(lights.sun_specs, res.study_K);
    std::unique_ptr<Tracer> tracer = make_embree_tracer(mesh);
    BakeOptions b = bake_options(o, res.study_K, Device::cpu);
    stage.say(fmt::format("sampling study: K = {}, reference Sobol S = {}", res.study_K,
                          res.study_reference_samples));
    // Another seed: Sobol sets are nested (the first S of the reference would be the S set).
    const TransferSet ref = bake_with_tracer(
        mesh, b, make_direction_set(SamplerKind::sobol, o.seed + 7919, res.study_reference_samples),
        *tracer);
    const std::vector<double> ref_sky = shade_luminance(mesh, ref, sky);
    const std::vector<double> ref_sun = shade_luminance(mesh, ref, sun);
    for (SamplerKind kind : kAllSamplerKinds)
        for (std::uint32_t S : S_list) {
            const TransferSet t =
                bake_with_tracer(mesh, b, make_direction_set(kind, o.seed, S), *tracer);
            StudyRow r;
            r.sampler = kind;
            r.samples = S;
            r.seconds = t.stats.seconds_total;
            const std::vector<double> y_sky = shade_luminance(mesh, t, sky);
            const std::vector<double> y_sun = shade_luminance(mesh, t, sun);
            r.sky_error = vertex_error(y_sky, truth.sky_y).relative_rmse();
            r.sun_error = vertex_error(y_sun, truth.sun_y).relative_rmse();
            r.sky_noise = vertex_error(y_sky, ref_sky).relative_rmse();
            r.sun_noise = vertex_error(y_sun, ref_sun).relative_rmse();
            res.study.push_back(r);
        }
    stage.say(fmt::format("sampling study: {} bakes done", res.study.size()));
}

}  // namespace shprt::paper
