// The enum name tables (core/names.hpp): names both ways, and the one error line.
#include "shprt/core/error.hpp"
#include "shprt/core/names.hpp"

#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <vector>

namespace shprt {
namespace {

enum class Colour { red, green, blue };
constexpr Named<Colour> kColourNames[] = {
    {Colour::red, "red"}, {Colour::green, "green"}, {Colour::blue, "blue"}};

TEST(Names, BothWays) {
    for (const Named<Colour>& entry : kColourNames) {
        EXPECT_STREQ(name_of(kColourNames, entry.value), entry.name);
        EXPECT_EQ(parse_named(kColourNames, entry.name, "colour"), entry.value);
    }
    EXPECT_STREQ(name_of(kColourNames, Colour(7)), "?");
}

TEST(Names, UnknownNameListsTheChoices) {
    try {
        parse_named(kColourNames, "Red", "colour");
        ADD_FAILURE() << "'Red' was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
        EXPECT_EQ(std::string(e.what()),
                  "unknown colour 'Red' (expected red, green or blue); did you mean 'red'?");
    }
    constexpr Named<Colour> one[] = {{Colour::red, "red"}};
    EXPECT_THROW(
        {
            try {
                parse_named(one, "", "colour");
            } catch (const Error& e) {
                EXPECT_EQ(std::string(e.what()), "unknown colour '' (expected red)");
                throw;
            }
        },
        Error);
}

// The "did you mean" of every unknown name: one edit per three characters, a swap of neighbours
// being one edit, case ignored; nothing for a word that is far from every name or too short to
// tell.
TEST(Names, ClosestNameForgivesSmallTypos) {
    const std::vector<std::string_view> commands = {"bake", "merge", "info", "scene", "sh"};
    EXPECT_EQ(closest_name("bkae", commands), "bake");  // a swap
    EXPECT_EQ(closest_name("bak", commands), "bake");   // a deletion
    EXPECT_EQ(closest_name("merg3", commands), "merge");
    EXPECT_EQ(closest_name("SCENE", commands), "scene");
    EXPECT_EQ(closest_name("xyzzy", commands), "");
    EXPECT_EQ(closest_name("sc", commands), "") << "two letters tell nothing";
    EXPECT_EQ(closest_name("mrgee", commands), "") << "two edits in five letters";
    const std::vector<std::string_view> options = {"--coeffs", "--samples", "-o", "--log-level"};
    EXPECT_EQ(closest_name("--coefs", options), "--coeffs");
    EXPECT_EQ(closest_name("--smaples", options), "--samples");
    EXPECT_EQ(closest_name("--loglevel", options), "--log-level");
    EXPECT_EQ(closest_name("-x", options), "");
    EXPECT_EQ(unknown_name_message("command", "bkae", commands),
              "unknown command 'bkae'; did you mean 'bake'?");
    EXPECT_EQ(unknown_name_message("command", "xyzzy", commands), "unknown command 'xyzzy'");
}

}  // namespace
}  // namespace shprt
