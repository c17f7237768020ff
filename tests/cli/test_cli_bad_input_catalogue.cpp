// The catalogue of bad input (issue 15): every case of tests/data/bad_input_catalogue.txt
// (its head says how a case is written) is one parameterised test: missing, empty, cut, corrupt
// and directory files, huge claimed counts, non-finite numbers, bad arguments and outputs that
// cannot be written. Each ends in its exit code and one error line, the last on stderr, that names
// the file (or option) and the problem, with no output file and no temporary left.
#include "cli/cli_test.hpp"
#include "shprt/io/shprt_format.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using shprt::test_support::run_shprt;
using shprt::test_support::RunResult;
using shprt::test_support::slurp;

struct Case {
    std::string name, files, args, needles;
    int exit_code = 1;
};

// gtest prints a case by its name.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::string trim(const std::string& s) {
    const std::size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, const std::string& by) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t at; (at = s.find(by, start)) != std::string::npos; start = at + by.size())
        parts.push_back(s.substr(start, at - start));
    parts.push_back(s.substr(start));
    return parts;
}

std::vector<Case> load_cases() {
    std::ifstream in(std::string(SHPRT_TEST_DATA_DIR) + "/bad_input_catalogue.txt");
    std::vector<Case> cases;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        const std::vector<std::string> f = split(line, "|");
        if (f.size() != 5) {
            cases.push_back({"malformed: " + line, "", "", "", -1});
            continue;
        }
        cases.push_back({trim(f[0]), trim(f[1]), trim(f[2]), trim(f[4]), std::stoi(trim(f[3]))});
    }
    return cases;
}

// \n, \r, \t, \xHH.
std::string unescape(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] != '\\' || i + 1 == s.size()) {
            out += s[i];
            continue;
        }
        const char c = s[++i];
        if (c == 'n')
            out += '\n';
        else if (c == 'r')
            out += '\r';
        else if (c == 't')
            out += '\t';
        else if (c == 'x' && i + 2 < s.size() + 1) {
            out += static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += c;
        }
    }
    return out;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
    for (std::size_t at = 0; (at = s.find(from, at)) != std::string::npos; at += to.size())
        s.replace(at, from.size(), to);
    return s;
}

class BadInputCatalogue : public ::testing::TestWithParam<Case> {
protected:
    static void SetUpTestSuite() {
        s_dir = fs::temp_directory_path() / ("shprt_catalogue_" + std::to_string(::getpid()));
        fs::remove_all(s_dir);
        fs::create_directories(s_dir);
        const RunResult r = run_shprt("bake builtin:plane --samples 16 --coeffs 4 -o '" +
                                          (s_dir / "good.shprt").string() + "'",
                                      s_dir);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        s_good = slurp(s_dir / "good.shprt");
        s_help = run_shprt("--help", s_dir).out;
    }
    static void TearDownTestSuite() { fs::remove_all(s_dir); }

    // Makes one file of the case's `files` column in `dir`.
    static void make(const std::string& spec, const fs::path& dir) {
        const std::vector<std::string> p = split(spec, ":");
        ASSERT_GE(p.size(), 2u) << spec;
        const fs::path path = dir / p[1];
        const std::string kind = p[0];
        if (kind == "dir") {
            fs::create_directories(path);
        } else if (kind == "fifo") {
            ASSERT_EQ(::mkfifo(path.c_str(), 0644), 0) << path;
        } else if (kind == "nulldev") {
            if (::mknod(path.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0)
                GTEST_SKIP() << "mknod " << path << " needs root";
        } else if (kind == "text") {
            std::ofstream(path, std::ios::binary)
                << unescape(spec.substr(kind.size() + p[1].size() + 2));
        } else if (kind == "copy") {
            std::ofstream(path, std::ios::binary) << s_good;
        } else if (kind == "cut") {
            const long n = std::stol(p.at(2));
            const std::size_t size = n >= 0 ? std::size_t(n) : s_good.size() - std::size_t(-n);
            std::ofstream(path, std::ios::binary) << s_good.substr(0, size);
        } else if (kind == "poke") {
            const long at = std::stol(p.at(2));
            std::string bytes = s_good;
            std::size_t pos = at >= 0 ? std::size_t(at) : bytes.size() - std::size_t(-at);
            for (std::size_t i = 0; i + 1 < p.at(3).size(); i += 2)
                bytes[pos++] = static_cast<char>(std::stoi(p[3].substr(i, 2), nullptr, 16));
            std::ofstream(path, std::ios::binary) << bytes;
        } else if (kind == "meta") {
            // The top-level number `"KEY": N` of the metadata set to VALUE, padded with spaces to
            // N's length (no offset moves), and the header's two CRCs recomputed, so that only
            // the reader's content checks can refuse it.
            const std::string key = "\"" + p.at(2) + "\": ", value = p.at(3);
            std::string bytes = s_good;
            std::uint64_t length = 0;
            std::memcpy(&length, bytes.data() + 32, 8);
            const std::size_t at = bytes.find(key, shprt::kShprtHeaderSize) + key.size();
            const std::size_t end = bytes.find_first_of(",\n}", at);
            ASSERT_LT(end, shprt::kShprtHeaderSize + length) << spec;
            ASSERT_LE(value.size(), end - at) << spec;
            bytes.replace(at, end - at, value + std::string(end - at - value.size(), ' '));
            const auto put_crc = [&](std::size_t offset, const char* data, std::size_t size) {
                const std::uint32_t crc = shprt::crc32(data, size);
                std::memcpy(bytes.data() + offset, &crc, 4);
            };
            put_crc(40, bytes.data() + shprt::kShprtHeaderSize, length);
            put_crc(44, bytes.data(), 44);
            std::ofstream(path, std::ios::binary) << bytes;
        } else {
            FAIL() << "unknown file kind in " << spec;
        }
    }

    static fs::path s_dir;
    static std::string s_good;
    static std::string s_help;  // `shprt --help`: which commands this build has
};

fs::path BadInputCatalogue::s_dir;
std::string BadInputCatalogue::s_good;
std::string BadInputCatalogue::s_help;

TEST_P(BadInputCatalogue, OneLineTheExitCodeAndNothingLeft) {
    const Case& c = GetParam();
    ASSERT_GE(c.exit_code, 0) << "malformed catalogue line: " << c.name;
    for (const char* command : {"shade ", "render ", "export ", "view "})
        if (c.args.rfind(command, 0) == 0 &&
            s_help.find(std::string("\n  ") + command) == std::string::npos)
            GTEST_SKIP() << command << "is not in this build (SHPRT_RENDER=OFF)";
    const fs::path dir = s_dir / replace_all(replace_all(c.name, " ", "_"), "=", "_");
    fs::remove_all(dir);
    fs::create_directories(dir / "out");
    if (!c.files.empty())
        for (const std::string& spec : split(c.files, ";")) {
            make(spec, dir);
            if (::testing::Test::IsSkipped()) return;
        }
    const auto expand = [&](const std::string& s) {
        return replace_all(replace_all(s, "{d}", dir.string()), "{o}", (dir / "out").string());
    };
    const RunResult r = run_shprt(expand(c.args), dir);

    shprt::test_support::expect_failure(r, c.exit_code, split(expand(c.needles), ";"));
    EXPECT_TRUE(fs::is_empty(dir / "out")) << "an output was left in out/";
    for (const auto& e : fs::recursive_directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos)
            << "temporary left: " << e.path();
    fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Cases, BadInputCatalogue, ::testing::ValuesIn(load_cases()),
                         [](const ::testing::TestParamInfo<Case>& param) {
                             std::string name;
                             for (const char ch : param.param.name)
                                 name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                             return name + "_" + std::to_string(param.index);
                         });

}  // namespace
