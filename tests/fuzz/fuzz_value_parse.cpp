// Fuzz target: the command-line value parsers. The first byte picks the parser, the rest is the
// text as it would come from the command line: numbers and integers (core/parse.hpp) and the
// check every numeric option of the tools runs (tools/common/number_options.hpp, through a small
// CLI11 app), number lists, light specs (analytic ones; files have their own target),
// YAW,PITCH,ROLL, cameras, vectors and image sizes (shade/camera.hpp), sampler, window and
// transfer names. Each either parses to a value that keeps the parser's promise or throws
// shprt::Error.
#include "common/number_options.hpp"
#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/light/light.hpp"
#include "shprt/light/light_setup.hpp"
#include "shprt/sh/sampler.hpp"
#include "shprt/sh/window.hpp"
#include "shprt/shade/camera.hpp"
#include "shprt/transfer/transfer.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

namespace {

void check(bool ok) {
    if (!ok) std::abort();
}

bool finite3(shprt::Vec3f v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// A numeric option of each CLI11 type, checked by check_numeric_options, given `text`.
void parse_option(const std::string& text, int type) {
    CLI::App app{"fuzz"};
    std::int64_t i = 0;
    std::uint64_t u = 0;
    double d = 0;
    int small = 0;
    app.add_option("--i", i);
    app.add_option("--u", u);
    app.add_option("--d", d);
    app.add_option("--small", small)->check(CLI::Range(1, 1024));
    shprt::tools::check_numeric_options(app);
    static const char* const kNames[] = {"--i", "--u", "--d", "--small"};
    std::vector<std::string> args{text, kNames[type % 4]};  // CLI11 parses a reversed vector
    try {
        app.parse(args);
        check(std::isfinite(d));
        check(small == 0 || (small >= 1 && small <= 1024));
    } catch (const CLI::ParseError&) {
        // CLI11's own refusals (e.g. a value that looks like an option); the tools map them to
        // exit code 2 or to the Error the check threw.
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const int which = data[0];
    const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
    try {
        switch (which % 13) {
            case 0: {
                double v = 0;
                if (shprt::parse_number(text, v)) check(std::isfinite(v));
                break;
            }
            case 1: {
                std::int64_t v = 0;
                (void)shprt::parse_integer(text, v);
                std::uint64_t u = 0;
                (void)shprt::parse_integer(text, u);
                break;
            }
            case 2: {
                for (double v : shprt::parse_numbers(text, "fuzz")) check(std::isfinite(v));
                check(shprt::parse_numbers(text, 3, "fuzz").size() == 3);
                break;
            }
            case 3:
                parse_option(text, which / 13);
                break;
            case 4:
            case 5: {
                // Light specs that name no file (file specs are fuzz_light_load's).
                if (!shprt::light_spec_files(text).empty()) break;
                const int K = 1 + (which / 13) % 16;
                const shprt::ShLight light = shprt::parse_light(text, K);
                check(light.K == K && light.coeffs.size() == std::size_t(3 * K));
                for (float c : light.coeffs) check(std::isfinite(c));
                break;
            }
            case 6: {
                const shprt::Vec3d r = shprt::parse_yaw_pitch_roll(text);
                check(std::isfinite(r.x) && std::isfinite(r.y) && std::isfinite(r.z));
                break;
            }
            case 7: {
                shprt::Camera camera;
                shprt::parse_camera(text, camera);
                check(finite3(camera.eye) && finite3(camera.target));
                check(finite3(camera.target - camera.eye) && !(camera.target == camera.eye));
                break;
            }
            case 8:
                check(finite3(shprt::parse_vec3(text, "--eye")));
                break;
            case 9: {
                int w = 0, h = 0;
                shprt::parse_size(text, w, h);
                check(w >= 1 && h >= 1 && w <= 16384 && h <= 16384);
                break;
            }
            case 10:
                (void)shprt::parse_sampler_kind(text);
                break;
            case 11:
                (void)shprt::parse_window_kind(text);
                break;
            case 12:
                (void)shprt::parse_transfer_kind(text);
                break;
        }
    } catch (const shprt::Error&) {
    }
    return 0;
}
