// Quality stage of the paper study (quality.hpp).
#include "paper/quality.hpp"

#include "shprt/sh/window.hpp"
#include "shprt/shade/shade.hpp"

#include <span>

namespace shprt::paper {
namespace {

LightScore score(const std::vector<double>& est, const std::vector<double>& truth) {
    LightScore s;
    s.error = vertex_error(est, truth);
    s.ringing = vertex_ringing(est, truth);
    return s;
}

void add_contrast(LightScore& s, const std::vector<double>& est, const std::vector<double>& truth,
                  const FloorSets& sets) {
    if (sets.lit_count == 0 || sets.shadow_count == 0) return;
    s.contrast = shadow_contrast(est, truth, sets.lit, sets.shadow);
    s.has_contrast = true;
}

}  // namespace

std::vector<double> shade_luminance(const Mesh& mesh, const TransferSet& t, const ShLight& light) {
    const ShadeResult r = shade_vertices(mesh, t, light, ShadeOptions{});
    return luminance(std::span<const Vec3f>(r.irradiance));
}

void score_row(KRow& row, const Mesh& mesh, const TransferSet& t, const TransferSet& ti,
               const ShLight& sky, const ShLight& sun, const Truth& truth) {
    const FloorSets& sets = truth.floor;
    row.sky = score(shade_luminance(mesh, t, sky), truth.sky_y);
    const std::vector<double> sun_y = shade_luminance(mesh, t, sun);
    row.sun = score(sun_y, truth.sun_y);
    add_contrast(row.sun, sun_y, truth.sun_y, sets);
    row.sky_improved = score(shade_luminance(mesh, ti, sky), truth.sky_y);
    const std::vector<double> improved_y = shade_luminance(mesh, ti, sun);
    row.sun_improved = score(improved_y, truth.sun_y);
    add_contrast(row.sun_improved, improved_y, truth.sun_y, sets);
    // Ringing control: the improved bake under the windowed sun light.
    for (WindowKind w : {WindowKind::hann, WindowKind::lanczos}) {
        ShLight windowed = sun;
        window_light(windowed, w);
        const std::vector<double> y = shade_luminance(mesh, ti, windowed);
        LightScore& ls = w == WindowKind::hann ? row.sun_hann : row.sun_lanczos;
        ls = score(y, truth.sun_y);
        add_contrast(ls, y, truth.sun_y, sets);
    }
}

}  // namespace shprt::paper
