// `shprt sh`: a small SH toolbox, thin over the library (sh/basis.hpp, sh/rotation.hpp).
//   shprt sh eval --bands N --dir X,Y,Z [--json]   N² basis values at the normalised direction
//   shprt sh rotate --bands N --zyz A,B,G [--method paper|ivanic]
//                                                   rotates N² coefficients read from stdin
//   shprt sh info                                   prints the conventions
// Values are printed one per line with %.17g (round-trip precision). Every bad argument is a
// one-line error (shprt::Error, printed by main) and exit code 1; options are checked here rather
// than by CLI11 so that the messages stay one line.
#include "common/command.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/rotation.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace shprt::tools {
namespace {

int parse_bands(const std::string& text) {
    SHPRT_CHECK(!text.empty(), invalid_argument, "sh: --bands N is required");
    std::int64_t n = 0;
    SHPRT_CHECK(parse_integer(text, n) == IntegerParse::ok, invalid_argument,
                "sh: --bands must be an integer, got '{}'", text);
    SHPRT_CHECK(n >= 1 && n <= kMaxBands, invalid_argument,
                "sh: --bands must be in [1, {}], got {}", kMaxBands, n);
    return static_cast<int>(n);
}

// "A,B,C" → three finite numbers (core/parse.hpp).
std::vector<double> parse_triple(const std::string& text, const char* option) {
    SHPRT_CHECK(!text.empty(), invalid_argument, "sh: {} X,Y,Z is required", option);
    return parse_numbers(text, 3, fmt::format("sh: {}", option));
}

void print_values(const std::vector<double>& values, bool json) {
    std::string out;
    char buf[64];
    if (json) out += '[';
    for (std::size_t i = 0; i < values.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%.17g", values[i] + 0.0);  // + 0.0: print −0 as 0
        if (json && i > 0) out += ", ";
        out += buf;
        if (!json) out += '\n';
    }
    if (json) out += "]\n";
    std::fwrite(out.data(), 1, out.size(), stdout);
}

struct EvalArgs {
    std::string bands, dir;
    bool json = false;
};

void run_eval(const EvalArgs& args) {
    const int bands = parse_bands(args.bands);
    const std::vector<double> d = parse_triple(args.dir, "--dir");
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    SHPRT_CHECK(len > 0 && std::isfinite(len), invalid_argument,
                "sh eval: --dir {},{},{} has no direction (zero or overflowing length)", d[0], d[1],
                d[2]);
    std::vector<double> y(sh_count(bands));
    sh_eval(bands, d[0] / len, d[1] / len, d[2] / len, y.data());
    print_values(y, args.json);
}

struct RotateArgs {
    std::string bands, zyz, method = "ivanic";
};

void run_rotate(const RotateArgs& args) {
    const int bands = parse_bands(args.bands);
    const std::vector<double> a = parse_triple(args.zyz, "--zyz");
    const RotationMethod method = parse_rotation_method(args.method);
    const int K = sh_count(bands);
    std::vector<double> in;
    std::string token;
    long line = 1;
    for (int ch = std::getchar();; ch = std::getchar()) {
        const bool end = ch == EOF;
        if (end || ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r') {
            if (!token.empty()) {
                double x = 0;
                SHPRT_CHECK(parse_number(token, x), invalid_argument,
                            "sh rotate: stdin line {}: '{}' is not a finite number", line, token);
                SHPRT_CHECK(static_cast<int>(in.size()) < K, invalid_argument,
                            "sh rotate: expected {} coefficients ({} bands) on stdin, got more", K,
                            bands);
                in.push_back(x);
                token.clear();
            }
            if (end) break;
            if (ch == '\n') ++line;
        } else {
            token += static_cast<char>(ch);
        }
    }
    SHPRT_CHECK(static_cast<int>(in.size()) == K, invalid_argument,
                "sh rotate: expected {} coefficients ({} bands) on stdin, got {}", K, bands,
                in.size());
    std::vector<double> out(K);
    ShRotation::from_zyz(a[0], a[1], a[2], bands, method).apply(in.data(), out.data(), K);
    print_values(out, false);
}

constexpr const char* kInfo =
    R"(shprt SH conventions (the paper's: Green 2003, "Spherical Harmonic Lighting: The Gritty Details")
basis       real spherical harmonics, orthonormal over the unit sphere: integral of y_i y_j = delta_ij
            y_l^m = sqrt(2) K_l^m cos(m phi)  P_l^m(cos theta)    m > 0
                  = sqrt(2) K_l^m sin(-m phi) P_l^-m(cos theta)   m < 0
                  =         K_l^0           P_l^0(cos theta)    m = 0
            K_l^m = sqrt((2l+1)(l-|m|)! / (4 pi (l+|m|)!))
phase       Condon-Shortley phase (-1)^m included in P_l^m (so y_1^1 = -sqrt(3/(4 pi)) x)
index       i = l(l+1) + m, l = 0, 1, ..., m = -l..l
bands       n bands = l from 0 to n-1 = n^2 coefficients; basis size K = the first K coefficients
            in index order (K need not be a square, e.g. 32, 48, 128: a partly filled last band
            is not rotation invariant; rotation treats its missing coefficients as zero)
axes        world space right-handed, +Y up (glTF); SH functions take the unit world vector (x, y, z)
angles      theta from +Z, phi from +X toward +Y: x = sin(theta)cos(phi), y = sin(theta)sin(phi),
            z = cos(theta); zonal functions are symmetric about +Z
equirect    u = 0.5 + atan2(d.x, -d.z)/(2 pi), v = acos(d.y)/pi (row 0 = zenith +Y, centre = -Z)
rotation    coefficients of g(d) = f(R^-1 d); --zyz A,B,G means R = Rz(G) Ry(B) Rz(A), radians
            methods: ivanic (Ivanic-Ruedenberg 1996 + 1998 errata), paper (Rz Rx(-pi/2) Rz Rx(pi/2) Rz)
radiometry  diffuse transfer T(w) = V(w) max(0, n.w); E = sum c_T c_L is irradiance;
            outgoing radiance = albedo/pi * E; uniform Monte Carlo weight 4 pi / S
max bands   )";

void run_info() {
    std::string text = kInfo;
    text +=
        std::to_string(kMaxBands) + " (" + std::to_string(sh_count(kMaxBands)) + " coefficients)\n";
    std::fwrite(text.data(), 1, text.size(), stdout);
}

const bool sh_registered = register_command(
    {"sh", "Spherical-harmonics toolbox: evaluate, rotate, print the conventions", 10,
     [](CLI::App& app) {
         app.require_subcommand(1);

         auto eval = std::make_shared<EvalArgs>();
         CLI::App* e = app.add_subcommand("eval", "Print the N^2 basis values at a direction");
         e->add_option("--bands", eval->bands, "Number of bands N (N^2 values), 1..64");
         e->add_option("--dir", eval->dir, "Direction X,Y,Z (normalised here)");
         e->add_flag("--json", eval->json, "Print a JSON array instead of one value per line");
         e->callback([eval] { run_eval(*eval); });

         auto rot = std::make_shared<RotateArgs>();
         CLI::App* r = app.add_subcommand(
             "rotate", "Rotate N^2 coefficients from stdin: g(d) = f(R^-1 d), R = Rz(G)Ry(B)Rz(A)");
         r->add_option("--bands", rot->bands, "Number of bands N (N^2 coefficients on stdin)");
         r->add_option("--zyz", rot->zyz, "ZYZ Euler angles A,B,G in radians");
         r->add_option("--method", rot->method, "paper or ivanic (default ivanic)");
         r->callback([rot] { run_rotate(*rot); });

         CLI::App* i = app.add_subcommand("info", "Print the SH conventions");
         i->callback([] { run_info(); });
     }});

}  // namespace
}  // namespace shprt::tools
