// Measurements behind the paper's quality rows (Parubets & Berestneva 2011, "Application of
// parallel computing technology to optimise a global illumination model", results table): the
// seed's СКО (root-mean-square error over vertices), ringing of truncated SH (Sloan 2008,
// "Stupid Spherical Harmonics Tricks", on negative lobes and overshoot), shadow contrast, and the
// 10–90 % edge width used for step responses in imaging.
#include "paper/paper_metrics.hpp"

#include "shprt/core/math.hpp"

#include "shprt/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shprt::paper {
namespace {

void check_sizes(std::size_t a, std::size_t b, std::size_t mask, const char* what) {
    SHPRT_CHECK(a == b, invalid_argument, "{}: {} estimates but {} reference values", what, a, b);
    SHPRT_CHECK(mask == 0 || mask == a, invalid_argument, "{}: mask has {} entries for {} values",
                what, mask, a);
}

bool selected(std::span<const std::uint8_t> mask, std::size_t i) {
    return mask.empty() || mask[i] != 0;
}

}  // namespace

double luminance(Vec3d c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

std::vector<double> luminance(std::span<const Vec3d> rgb) {
    std::vector<double> out(rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i) out[i] = luminance(rgb[i]);
    return out;
}

std::vector<double> luminance(std::span<const Vec3f> rgb) {
    std::vector<double> out(rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i) out[i] = luminance(cast<double>(rgb[i]));
    return out;
}

VertexError vertex_error(std::span<const double> estimate, std::span<const double> reference,
                         std::span<const std::uint8_t> mask) {
    check_sizes(estimate.size(), reference.size(), mask.size(), "vertex_error");
    VertexError e;
    double sum_sq = 0, sum_diff = 0, sum_ref = 0;
    for (std::size_t i = 0; i < estimate.size(); ++i) {
        if (!selected(mask, i)) continue;
        const double d = estimate[i] - reference[i];
        sum_sq += d * d;
        sum_diff += d;
        sum_ref += reference[i];
        e.max_abs = std::max(e.max_abs, std::fabs(d));
        ++e.count;
    }
    SHPRT_CHECK(e.count > 0, invalid_argument, "vertex_error: no vertex selected");
    const double n = static_cast<double>(e.count);
    e.rmse = std::sqrt(sum_sq / n);
    e.bias = sum_diff / n;
    e.mean_reference = sum_ref / n;
    return e;
}

VertexRinging vertex_ringing(std::span<const double> estimate, std::span<const double> reference,
                             std::span<const std::uint8_t> mask) {
    check_sizes(estimate.size(), reference.size(), mask.size(), "vertex_ringing");
    VertexRinging r;
    double max_ref = -std::numeric_limits<double>::infinity(), sum_ref = 0;
    for (std::size_t i = 0; i < estimate.size(); ++i) {
        if (!selected(mask, i)) continue;
        max_ref = std::max(max_ref, reference[i]);
        sum_ref += reference[i];
        ++r.count;
    }
    SHPRT_CHECK(r.count > 0, invalid_argument, "vertex_ringing: no vertex selected");
    std::size_t negative = 0, over = 0;
    for (std::size_t i = 0; i < estimate.size(); ++i) {
        if (!selected(mask, i)) continue;
        if (estimate[i] < 0) ++negative;
        if (estimate[i] > max_ref) ++over;
        r.most_negative = std::min(r.most_negative, estimate[i]);
    }
    const double n = static_cast<double>(r.count);
    r.negative_fraction = double(negative) / n;
    r.overshoot_fraction = double(over) / n;
    const double mean_ref = sum_ref / n;
    r.most_negative_relative = mean_ref != 0 ? r.most_negative / mean_ref : 0;
    return r;
}

ShadowContrast shadow_contrast(std::span<const double> estimate, std::span<const double> reference,
                               std::span<const std::uint8_t> lit,
                               std::span<const std::uint8_t> shadow) {
    check_sizes(estimate.size(), reference.size(), lit.size(), "shadow_contrast");
    SHPRT_CHECK(lit.size() == estimate.size() && shadow.size() == estimate.size(), invalid_argument,
                "shadow_contrast: masks have {} and {} entries for {} values", lit.size(),
                shadow.size(), estimate.size());
    ShadowContrast c;
    double sum_sq = 0;
    for (std::size_t i = 0; i < estimate.size(); ++i) {
        if (lit[i]) {
            c.estimate_lit += estimate[i];
            c.reference_lit += reference[i];
            ++c.lit_count;
        }
        if (shadow[i]) {
            c.estimate_shadow += estimate[i];
            c.reference_shadow += reference[i];
            sum_sq += (estimate[i] - reference[i]) * (estimate[i] - reference[i]);
            ++c.shadow_count;
        }
    }
    SHPRT_CHECK(c.lit_count > 0 && c.shadow_count > 0, invalid_argument,
                "shadow_contrast: {} lit and {} shadowed vertices; both sets must be non-empty",
                c.lit_count, c.shadow_count);
    const double nl = static_cast<double>(c.lit_count), ns = static_cast<double>(c.shadow_count);
    c.estimate_lit /= nl;
    c.reference_lit /= nl;
    c.estimate_shadow /= ns;
    c.reference_shadow /= ns;
    const double reference_contrast = c.reference_lit - c.reference_shadow;
    SHPRT_CHECK(reference_contrast > 0, invalid_argument,
                "shadow_contrast: the reference is no brighter in the lit set ({}) than in the "
                "shadowed set ({})",
                c.reference_lit, c.reference_shadow);
    c.saturation = (c.estimate_lit - c.estimate_shadow) / reference_contrast;
    c.shadow_fill_error = std::sqrt(sum_sq / ns) / reference_contrast;
    return c;
}

Profile image_profile(const Image& image, const Camera& camera, Vec3f a, Vec3f b, int count) {
    SHPRT_CHECK(count >= 2, invalid_argument, "image_profile: {} samples; need at least 2", count);
    SHPRT_CHECK(!image.empty() && image.rgb.size() == image.pixel_count() * 3, invalid_argument,
                "image_profile: empty or malformed image");
    Profile p;
    const double len = length(cast<double>(b - a));
    for (int k = 0; k < count; ++k) {
        const double s = double(k) / double(count - 1);
        const Vec3f q = a + (b - a) * static_cast<float>(s);
        float x, y, depth;
        SHPRT_CHECK(
            project_to_pixel(camera, image.width, image.height, q, x, y, depth), invalid_argument,
            "image_profile: point ({}, {}, {}) is outside the {}x{} image or behind the eye", q.x,
            q.y, q.z, image.width, image.height);
        // Pixel (i, j) has its centre at (i + 0.5, j + 0.5): interpolate between centres,
        // clamping at the border.
        const double fx = std::clamp(double(x) - 0.5, 0.0, double(image.width - 1));
        const double fy = std::clamp(double(y) - 0.5, 0.0, double(image.height - 1));
        const int x0 = std::min(int(fx), image.width - 1), y0 = std::min(int(fy), image.height - 1);
        const int x1 = std::min(x0 + 1, image.width - 1), y1 = std::min(y0 + 1, image.height - 1);
        const double tx = fx - x0, ty = fy - y0;
        const auto lum = [&](int px, int py) {
            const float* c = image.pixel(px, py);
            return luminance(Vec3d{c[0], c[1], c[2]});
        };
        const double v = (1 - ty) * ((1 - tx) * lum(x0, y0) + tx * lum(x1, y0)) +
                         ty * ((1 - tx) * lum(x0, y1) + tx * lum(x1, y1));
        p.position.push_back(s * len);
        p.value.push_back(v);
    }
    return p;
}

EdgeMeasure measure_edge(const Profile& profile, double plateau) {
    const std::size_t n = profile.value.size();
    SHPRT_CHECK(profile.position.size() == n, invalid_argument,
                "measure_edge: {} positions for {} values", profile.position.size(), n);
    SHPRT_CHECK(n >= 4, invalid_argument, "measure_edge: {} samples; need at least 4", n);
    SHPRT_CHECK(plateau > 0 && plateau < 0.5, invalid_argument,
                "measure_edge: plateau share {} must be in (0, 0.5)", plateau);
    const std::size_t m = std::max<std::size_t>(1, static_cast<std::size_t>(plateau * double(n)));
    EdgeMeasure e;
    for (std::size_t i = 0; i < m; ++i) {
        e.high += profile.value[i];
        e.low += profile.value[n - 1 - i];
    }
    e.high /= double(m);
    e.low /= double(m);
    if (!(e.high > e.low)) return e;  // no edge to measure
    const double range = e.high - e.low;
    const auto t = [&](std::size_t i) { return (profile.value[i] - e.low) / range; };
    const auto cross = [&](std::size_t i, std::size_t j, double level) {
        // Linear interpolation of the level's position between samples i and j.
        const double ti = t(i), tj = t(j);
        const double f = ti != tj ? std::clamp((level - ti) / (tj - ti), 0.0, 1.0) : 0.0;
        return profile.position[i] + f * (profile.position[j] - profile.position[i]);
    };
    // x90: the first sample below 0.9 from the start.
    std::size_t i90 = 0;
    while (i90 < n && t(i90) >= 0.9) ++i90;
    if (i90 == n) return e;  // never leaves the lit level
    e.x90 = i90 == 0 ? profile.position[0] : cross(i90 - 1, i90, 0.9);
    // x10: the last sample above 0.1 from the end.
    std::size_t i10 = n;
    while (i10 > 0 && t(i10 - 1) <= 0.1) --i10;
    if (i10 == 0) return e;  // never above the dark level
    const std::size_t last_above = i10 - 1;
    e.x10 = last_above + 1 < n ? cross(last_above, last_above + 1, 0.1) : profile.position[n - 1];
    e.width = e.x10 - e.x90;
    const auto [lo, hi] = std::minmax_element(profile.value.begin(), profile.value.end());
    e.overshoot = std::max(0.0, (*hi - e.high) / range);
    e.undershoot = std::max(0.0, (e.low - *lo) / range);
    e.valid = true;
    return e;
}

TransferSet irradiance_as_transfer(std::span<const Vec3d> irradiance) {
    TransferSet t;
    t.kind = TransferKind::shadowed;
    t.layout.K = 1;
    t.layout.channels = 3;
    t.coeffs.resize(irradiance.size() * 3);
    const double inv = 1.0 / std::sqrt(4.0 * kPi);
    for (std::size_t v = 0; v < irradiance.size(); ++v)
        for (int c = 0; c < 3; ++c)
            t.coeffs[v * 3 + c] = static_cast<float>(irradiance[v][c] * inv);
    return t;
}

}  // namespace shprt::paper
