// The header checks that run before Assimp sees a file (src/scene/ply_header.hpp): here the OFF
// counts, which Assimp 5.2.5 allocates before it reads a vertex.
#include "../src/scene/ply_header.hpp"
#include "shprt/core/error.hpp"

#include <gtest/gtest.h>

#include <string>

namespace shprt {
namespace {

using detail::check_off_header;

void check(const std::string& text) { check_off_header("t.off", text, text.size()); }

TEST(OffHeader, CountsTheFileCanHoldPass) {
    check("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    check("# a comment\n\nCOFF 3 1 0\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n");
    check("OFF\n# counts after a comment\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    // Not an OFF header, or counts that do not parse: Assimp decides.
    check("ply\nformat ascii 1.0\n");
    check("nOFF\n3\n99999999 1 0\n");
    check("OFF\nmany 1 0\n");
}

// Found by fuzz_scene_load (tests/fuzz/corpus/scene_load/off-huge-count): 1e8 vertices claimed by
// a 130-byte file took Assimp 1.2 GB and 1.5 s (7 s under ASan) before it failed.
TEST(OffHeader, CountsBeyondTheFileAreRefused) {
    EXPECT_THROW(check("OFF\n000104710033 6 0\n-0.5 -0.5 0\n0.5 -0.5 0.5\n"), Error);
    EXPECT_THROW(check("OFF\n353535235358 6 0\n"), Error);
    EXPECT_THROW(check("OFF\n3 1000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), Error);
    try {
        check("OFF 100 1 0\n");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::format);
        EXPECT_EQ(std::string(e.what()),
                  "t.off: the OFF header claims 100 vertices and 1 faces, "
                  "more than a file of 12 bytes can hold");
    }
}

}  // namespace
}  // namespace shprt
