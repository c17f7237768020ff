// Outputs that must not be written, and error lines that must stay short (issue 41, items 3, 4,
// 10 and 11): an output that exists and is not a regular file (a FIFO, a device) is refused, not
// replaced; so is every file the scene reads (an OBJ's material library, a texture); every
// writing command refuses an output it cannot write before its work; a library's message adds at
// most 200 bytes to an error line; a camera without a frame names its option or file; compress
// refuses --threads -1 as bake does.
#include "cli/cli_test.hpp"
#include "shprt/config.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using shprt::test_support::expect_one_line_error;
using shprt::test_support::RunResult;
using shprt::test_support::slurp;

class CliOutputs : public shprt::test_support::CliTest {
protected:
    std::string path(const std::string& name) const { return (m_dir / name).string(); }
    // A small bake for the commands that read one.
    std::string baked() {
        const std::string p = path("plane.shprt");
        if (!fs::exists(p)) {
            EXPECT_EQ(shprt("bake builtin:plane --samples 16 --coeffs 4 -o '" + p + "'").exit_code,
                      0);
        }
        return p;
    }
    // Every command that writes a file, with OUT where its output goes, and the extension OUT
    // needs.
    std::vector<std::pair<std::string, std::string>> writers() {
        const std::string in = "'" + baked() + "'";
        std::vector<std::pair<std::string, std::string>> all = {
            {"bake builtin:plane --samples 16 -o OUT", ".shprt"},
            {"bake builtin:plane --samples 16 --stream -o OUT", ".shprt"},
            {"compress " + in + " --cpca 1,1 -o OUT", ".shprt"},
            {"merge " + in + " -o OUT", ".shprt"},
            {"scene room -o OUT", ".ply"},
        };
        if (SHPRT_HAS_RENDER) {  // the commands that draw come with the renderer
            all.push_back({"shade " + in + " --light constant:1 -o OUT", ".csv"});
            all.push_back({"render " + in + " --light constant:1 --size 32x24 -o OUT", ".png"});
            all.push_back({"export " + in + " --light constant:1 -o OUT", ".glb"});
        }
        return all;
    }
    static std::string with_output(std::string command, const std::string& output) {
        command.replace(command.find("OUT"), 3, "'" + output + "'");
        return command;
    }
};

// A FIFO, and a character device (the null device, as root only), as the output: refused in one
// line naming it, and still there, unchanged in kind.
TEST_F(CliOutputs, OutputsThatAreNotRegularFilesAreRefused) {
    bool have_device = true;
    for (const auto& [command, extension] : writers()) {
        SCOPED_TRACE(command);
        const std::string fifo = path("ff" + extension), device = path("nulldev" + extension);
        if (!fs::exists(fifo)) ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
        if (!fs::exists(device))
            have_device = ::mknod(device.c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0;
        expect_one_line_error(shprt(with_output(command, fifo)),
                              "cannot write " + fifo + ": it exists and is a FIFO");
        EXPECT_TRUE(fs::is_fifo(fifo));
        if (have_device) {
            expect_one_line_error(shprt(with_output(command, device)),
                                  "cannot write " + device + ": it exists and is a character");
            EXPECT_TRUE(fs::is_character_file(device));
        }
    }
    if (!have_device) GTEST_SKIP() << "mknod needs root: the device case was not run";
}

// An OBJ's material library (and a texture its material names) are inputs: `-o tri.mtl` is
// refused and the file is unchanged (issue 41's reproduction ended with the .mtl gone).
TEST_F(CliOutputs, FilesTheSceneReadsAreInputs) {
    const std::string obj = path("tri.obj"), mtl = path("tri.mtl"), png = path("tex.png");
    std::ofstream(obj) << "mtllib tri.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n"
                          "vt 0 1\nf 1/1 2/2 3/3\n";
    std::ofstream(mtl) << "newmtl red\nKd 1 0 0\nmap_Kd tex.png\n";
    std::ofstream(png) << "not really a png";
    for (const std::string& target : {mtl, png}) {
        for (const std::string& mode : {std::string(""), std::string(" --stream")}) {
            SCOPED_TRACE(target + mode);
            const std::string before = slurp(target);
            const RunResult r =
                shprt("bake '" + obj + "' --samples 16" + mode + " -o '" + target + "'");
            shprt::test_support::expect_failure(r, 1,
                                                {"output " + target, "which the scene reads"});
            EXPECT_EQ(slurp(target), before);
        }
    }
}

// shade, render, export, compress and merge check their output before the work, as bake does: a
// directory is refused before the input is read (here a cut file, whose error would come first).
TEST_F(CliOutputs, OutputIsCheckedBeforeTheWork) {
    const std::string cut = path("cut.shprt");
    const std::string whole = slurp(baked());
    std::ofstream(cut, std::ios::binary) << whole.substr(0, whole.size() - 100);
    for (auto [command, extension] : writers()) {
        if (command.rfind("bake", 0) == 0 || command.rfind("scene", 0) == 0) continue;
        command.replace(command.find("'" + baked() + "'"), baked().size() + 2, "'" + cut + "'");
        SCOPED_TRACE(command);
        const std::string dir = path("dir" + extension);
        fs::create_directories(dir);
        expect_one_line_error(shprt(with_output(command, dir)),
                              "cannot write " + dir + ": it is a directory");
    }
}

// Assimp quotes the rest of a corrupt file in some messages (an SMD with one bad byte gave a
// 916 917-byte line): what a library's message adds is cut at 200 bytes, with "…".
TEST_F(CliOutputs, LibraryMessagesAreCut) {
    std::string smd =
        "version 1\nnodes\n  0 \"root\"  -1\nend\nskeleton\ntime 0\n  0 0 0 0 0 0 0\nend\n"
        "triangles\n";
    const std::string triangle =
        "none.bmp\n0  0.0 0.0 0.0 1.0 1.0 1.0 0.0 0.0\n0  1.0 0.0 0.0 1.0 1.0 1.0 1.0 0.0\n"
        "0  1.0 1.0 0.0 1.0 1.0 1.0 1.0 1.0\n";
    smd += triangle +
           "0 \xff"
           "04 0.0 0.0 1.0 1.0 1.0 0.0 0.0\n";
    for (int i = 0; i < 400; ++i) smd += triangle;
    smd += "end\n";
    const std::string file = path("g.smd");
    std::ofstream(file, std::ios::binary) << smd;
    const RunResult r = shprt("scene info '" + file + "'");
    expect_one_line_error(r, "g.smd: cannot read the scene: ");
    EXPECT_LT(r.err.size(), file.size() + 300) << r.err.substr(0, 400);
    EXPECT_NE(r.err.find("…"), std::string::npos);
}

// A camera that has no frame names where it came from.
TEST_F(CliOutputs, CameraWithoutAFrameNamesItsOptionOrFile) {
    if (!SHPRT_HAS_RENDER) GTEST_SKIP() << "`render` comes with the renderer (SHPRT_RENDER=OFF)";
    expect_one_line_error(
        shprt("render '" + baked() + "' --light constant:1 --camera 1e30,1e30,1e30,0,0,0 -o '" +
              out("r.png") + "'"),
        "--camera 1e30,1e30,1e30,0,0,0");
    const std::string big = path("big.obj");
    std::ofstream(big) << "v 0 0 0\nv 3e38 0 0\nv 0 3e38 0\nf 1 2 3\n";
    const std::string baked_big = path("big.shprt");
    if (shprt("bake '" + big + "' --samples 16 --coeffs 4 -o '" + baked_big + "'").exit_code == 0)
        expect_one_line_error(
            shprt("render '" + baked_big + "' --light constant:1 -o '" + out("r.png") + "'"),
            baked_big);
}

TEST_F(CliOutputs, CompressRefusesNegativeThreadsAsBakeDoes) {
    expect_one_line_error(
        shprt("compress '" + baked() + "' --cpca 1,1 --threads -1 -o '" + out("c.shprt") + "'"),
        "--threads -1: must be 0 (all) to");
    expect_one_line_error(shprt("bake builtin:plane --threads -1 -o '" + out("b.shprt") + "'"),
                          "--threads -1: must be 0 (all) to");
    EXPECT_TRUE(out_dir_empty());
}

}  // namespace
