// `shprt sh`: a small SH toolbox, thin over the library (sh/basis.hpp, sh/rotation.hpp).
//   shprt sh eval --bands N --dir X,Y,Z [--json]   N² basis values at the normalised direction
//   shprt sh rotate --bands N --zyz A,B,G [--method paper|ivanic]
//                                                   rotates N² coefficients read from stdin
//   shprt sh info                                   prints the conventions (sh/conventions.hpp)
// Values are printed one per line with %.17g (round-trip precision). Every bad argument is a
// one-line error (shprt::Error, printed by main) and exit code 1; options are checked here rather
// than by CLI11 so that the messages stay one line.
#include "common/command.hpp"

#include "shprt/core/error.hpp"
#include "shprt/core/parse.hpp"
#include "shprt/core/rotation3.hpp"
#include "shprt/sh/basis.hpp"
#include "shprt/sh/conventions.hpp"
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

void run_info() {
    const std::string text = sh_conventions_text();
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
