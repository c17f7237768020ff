// Light specs, sums, rotation and windowing of SH light vectors. Rotation goes through the SH
// rotation of sh/rotation.hpp (Ivanic & Ruedenberg 1996; Sloan, Kautz & Snyder 2002 §6 rotate
// the light, never re-project it).
#include "shprt/light/light.hpp"
#include "shprt/light/sun.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/file.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string_view>

namespace shprt {
namespace {

constexpr const char* kSpecHelp =
    "expected FILE.hdr|FILE.exr|FILE.png (2:1 equirect or 4:3/3:4 cube cross), equirect:FILE, "
    "cross:FILE, faces:PX,NX,PY,NY,PZ,NZ, constant[:V|:R,G,B], "
    "gradient[:ZR,ZG,ZB[:HR,HG,HB[:GR,GG,GB]]], sun:X,Y,Z[,RADIUS_DEG[,R,G,B]] or builtin";

std::vector<std::string_view> split(std::string_view text, char sep) {
    std::vector<std::string_view> parts;
    std::size_t start = 0;
    for (;;) {
        const std::size_t end = text.find(sep, start);
        parts.push_back(text.substr(start, end == std::string_view::npos ? end : end - start));
        if (end == std::string_view::npos) break;
        start = end + 1;
    }
    return parts;
}

// Comma-separated finite numbers (core/parse.hpp), any count; throws naming the spec.
std::vector<double> spec_numbers(std::string_view text, const std::string& spec) {
    return parse_numbers(text, "light '" + spec + "'");
}

Vec3d parse_rgb(std::string_view text, const std::string& spec, const char* what) {
    const std::vector<double> v = spec_numbers(text, spec);
    SHPRT_CHECK(v.size() == 3, invalid_argument,
                "light '{}': {} needs three numbers R,G,B, got '{}'", spec, what, text);
    return {v[0], v[1], v[2]};
}

bool has_image_extension(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".hdr" || ext == ".exr" || ext == ".png";
}

// A light's radiance is never negative (nor NaN or infinite: load_image refuses those): the same
// rule as for constant:V, sun and gradient colours. Checked on every map a light reads.
void check_radiance_row(const std::string& path, int y, int width, const float* rgb) {
    for (std::size_t i = 0; i < 3 * std::size_t(width); ++i) {
        if (rgb[i] < 0.0f)
            fail(ErrorCode::format,
                 "image {} has a negative value {} at pixel ({}, {}) channel {}: a light's "
                 "radiance must be ≥ 0",
                 path, rgb[i], i / 3, y, "RGB"[i % 3]);
    }
}

Image load_radiance_map(const std::string& path, const ImageSizeCheck& check_size = {}) {
    Image image = load_image(path, check_size);
    check_radiance_map(path, image);
    return image;
}

ShLight light_from_file(const std::string& path, int K, char layout /* 'a'uto, 'e', 'c' */) {
    SHPRT_CHECK(!path.empty(), invalid_argument, "missing file name");
    const auto equirect_shape = [](int W, int H) { return W == 2 * H; };
    const auto cross_shape = [](int W, int H) {
        return (W % 4 == 0 && H % 3 == 0 && W / 4 == H / 3) ||
               (W % 3 == 0 && H % 4 == 0 && W / 3 == H / 4);
    };
    // The shape is checked from the header, before the pixels are decoded. An equirect map is
    // projected row by row as it is read (read_image_rows), so a large map is never held whole; a
    // cube cross is gathered, its faces being squares across rows.
    std::optional<EquirectProjection> equirect;
    Image cross;
    read_image_rows(
        path,
        [&](int W, int H) {
            if (layout == 'e' || (layout == 'a' && equirect_shape(W, H))) {
                equirect.emplace(W, H, K);
                return;
            }
            SHPRT_CHECK(cross_shape(W, H), format,
                        "image {} is {}x{}: expected an equirect map of aspect 2:1 (e.g. "
                        "2048x1024) or a cube cross of aspect 4:3 or 3:4 with square faces (e.g. "
                        "1024x768)",
                        path, W, H);
            cross = Image::make(W, H);
        },
        [&](int y, const float* rgb) {
            const int width = equirect ? equirect->width() : cross.width;
            check_radiance_row(path, y, width, rgb);
            if (equirect)
                equirect->add_row(rgb);
            else
                std::copy(rgb, rgb + 3 * std::size_t(width), cross.pixel(0, y));
        });
    return equirect ? equirect->finish() : project_cube_cross(cross, K);
}

ShLight parse_light_unwrapped(const std::string& spec, int K) {
    const std::size_t colon = spec.find(':');
    const std::string head = spec.substr(0, colon);
    const bool has_args = colon != std::string::npos;
    const std::string_view args =
        has_args ? std::string_view(spec).substr(colon + 1) : std::string_view();

    if (head == "builtin") {
        SHPRT_CHECK(!has_args, invalid_argument, "light '{}': builtin takes no arguments", spec);
        return builtin_light(K);
    }
    if (head == "constant") {
        if (!has_args) return constant_light({1, 1, 1}, K);
        const std::vector<double> v = spec_numbers(args, spec);
        SHPRT_CHECK(v.size() == 1 || v.size() == 3, invalid_argument,
                    "light '{}': expected constant, constant:V or constant:R,G,B", spec);
        return constant_light(v.size() == 1 ? Vec3d{v[0], v[0], v[0]} : Vec3d{v[0], v[1], v[2]}, K);
    }
    if (head == "gradient") {
        GradientSky sky;
        if (has_args) {
            const std::vector<std::string_view> parts = split(args, ':');
            SHPRT_CHECK(
                parts.size() <= 3, invalid_argument,
                "light '{}': expected gradient[:ZENITH_R,G,B[:HORIZON_R,G,B[:GROUND_R,G,B]]]",
                spec);
            sky.zenith = parse_rgb(parts[0], spec, "the zenith colour");
            if (parts.size() > 1) sky.horizon = parse_rgb(parts[1], spec, "the horizon colour");
            if (parts.size() > 2) sky.ground = parse_rgb(parts[2], spec, "the ground colour");
        }
        return gradient_light(sky, K);
    }
    if (head == "sun") {
        SHPRT_CHECK(has_args, invalid_argument,
                    "light '{}': expected sun:X,Y,Z[,RADIUS_DEG[,R,G,B]]", spec);
        // The one sun model (light/sun.hpp), shared with `--sun`.
        return sun_light(parse_sun(args, "light '" + spec + "'", "sun:X,Y,Z[,RADIUS_DEG[,R,G,B]]"),
                         K);
    }
    if (head == "equirect" && has_args) return light_from_file(std::string(args), K, 'e');
    if (head == "cross" && has_args) return light_from_file(std::string(args), K, 'c');
    if (head == "faces" && has_args) {
        const std::vector<std::string_view> files = split(args, ',');
        SHPRT_CHECK(files.size() == 6, invalid_argument,
                    "light '{}': expected faces:PX,NX,PY,NY,PZ,NZ (six files), got {}", spec,
                    files.size());
        std::array<Image, 6> faces;
        for (int f = 0; f < 6; ++f) {
            SHPRT_CHECK(!files[f].empty(), invalid_argument, "light '{}': face {} has no file name",
                        spec, f + 1);
            faces[f] = load_radiance_map(std::string(files[f]));
        }
        return project_cube_faces(faces, K);
    }
    if (has_image_extension(spec)) return light_from_file(spec, K, 'a');
    fail(ErrorCode::invalid_argument, "unknown light '{}': {}", spec, kSpecHelp);
}

}  // namespace

// Float overflow: a finite but huge radiance (constant:1e38, an RGBE pixel with exponent 255)
// projects to infinite coefficients, which would shade to inf and NaN.
void check_finite_light(const ShLight& light, const std::string& what) {
    for (std::size_t i = 0; i < light.coeffs.size(); ++i) {
        const std::size_t k = i % std::size_t(light.K);
        const char channel = "RGB"[i / std::size_t(light.K)];
        SHPRT_CHECK(!std::isnan(light.coeffs[i]), invalid_argument,
                    "{} is not a number: its SH coefficient {} of channel {} is NaN", what, k,
                    channel);
        SHPRT_CHECK(std::isfinite(light.coeffs[i]), invalid_argument,
                    "{} is too bright: its SH coefficient {} of channel {} overflows float", what,
                    k, channel);
    }
}

void check_radiance_map(const std::string& name, const Image& image) {
    check_image_finite(name, image);
    for (int y = 0; y < image.height; ++y)
        check_radiance_row(name, y, image.width, image.pixel(0, y));
}

ShLight ShLight::zero(int K) {
    SHPRT_CHECK(K >= 1 && K <= kMaxLightK, invalid_argument,
                "light basis size K = {} must be in [1, {}]", K, kMaxLightK);
    ShLight light;
    light.K = K;
    light.coeffs.assign(3 * std::size_t(K), 0.0f);
    return light;
}

void add_light(ShLight& a, const ShLight& b) {
    SHPRT_CHECK(a.K == b.K && a.coeffs.size() == b.coeffs.size(), invalid_argument,
                "cannot add lights of basis sizes {} and {}", a.K, b.K);
    for (std::size_t i = 0; i < a.coeffs.size(); ++i) a.coeffs[i] += b.coeffs[i];
}

Vec3d light_radiance(const ShLight& light, Vec3d d) {
    SHPRT_CHECK(light.K >= 1 && light.coeffs.size() == 3 * std::size_t(light.K), invalid_argument,
                "light_radiance: malformed light (K = {}, {} coefficients)", light.K,
                light.coeffs.size());
    std::vector<double> y(light.K);
    sh_eval_k(light.K, d.x, d.y, d.z, y.data());
    Vec3d out{0, 0, 0};
    for (int c = 0; c < 3; ++c) {
        double s = 0.0;
        for (int i = 0; i < light.K; ++i) s += double(light.channel(c)[i]) * y[i];
        out[c] = s;
    }
    return out;
}

ShLight parse_light(const std::string& spec, int K) {
    SHPRT_CHECK(!spec.empty(), invalid_argument, "empty light spec: {}", kSpecHelp);
    ShLight::zero(K);  // validate K first, with its own message
    try {
        ShLight light = parse_light_unwrapped(spec, K);
        check_finite_light(light, "light '" + spec + "'");
        return light;
    } catch (const Error& e) {
        const std::string what = e.what();
        // Messages that already quote the spec are passed on; others get it prefixed.
        if (what.find("'" + spec + "'") != std::string::npos) throw;
        throw Error(e.code(), fmt::format("light '{}': {}", spec, what));
    }
}

std::vector<std::string> light_spec_files(const std::string& spec) {
    const std::size_t colon = spec.find(':');
    const std::string head = spec.substr(0, colon);
    const std::string args = colon == std::string::npos ? std::string() : spec.substr(colon + 1);
    if ((head == "equirect" || head == "cross") && !args.empty()) return {args};
    if (head == "faces" && !args.empty()) {
        std::vector<std::string> files;
        for (std::string_view f : split(args, ',')) files.emplace_back(f);
        return files;
    }
    if (has_image_extension(spec)) return {spec};
    return {};
}

ShLight make_light(const std::vector<std::string>& specs, int K) {
    if (specs.empty()) return parse_light("builtin", K);
    ShLight sum = parse_light(specs[0], K);
    for (std::size_t i = 1; i < specs.size(); ++i) add_light(sum, parse_light(specs[i], K));
    if (specs.size() > 1) check_finite_light(sum, "the sum of the lights");
    return sum;
}

void rotate_light(ShLight& light, const Mat3d& R) {
    const int K = light.K;
    SHPRT_CHECK(K >= 1 && light.coeffs.size() == 3 * std::size_t(K), invalid_argument,
                "rotate_light: malformed light (K = {}, {} coefficients)", K, light.coeffs.size());
    const ShRotation rot = ShRotation::from_matrix(R, sh_bands_for(K));
    std::vector<double> in(K), out(K);
    for (int c = 0; c < 3; ++c) {
        float* ch = light.channel(c);
        for (int i = 0; i < K; ++i) in[i] = ch[i];
        rot.apply(in.data(), out.data(), K);
        for (int i = 0; i < K; ++i) ch[i] = static_cast<float>(out[i]);
    }
}

void window_light(ShLight& light, WindowKind kind, double strength) {
    const int K = light.K;
    SHPRT_CHECK(K >= 1 && light.coeffs.size() == 3 * std::size_t(K), invalid_argument,
                "window_light: malformed light (K = {}, {} coefficients)", K, light.coeffs.size());
    std::vector<double> buf(K);
    for (int c = 0; c < 3; ++c) {
        float* ch = light.channel(c);
        for (int i = 0; i < K; ++i) buf[i] = ch[i];
        apply_window(kind, buf.data(), K, strength);
        for (int i = 0; i < K; ++i) ch[i] = static_cast<float>(buf[i]);
    }
}

}  // namespace shprt
