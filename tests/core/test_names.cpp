// The enum name tables (core/names.hpp): names both ways, and the one error line.
#include "shprt/core/error.hpp"
#include "shprt/core/names.hpp"

#include <gtest/gtest.h>

#include <string>

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
        EXPECT_EQ(std::string(e.what()), "unknown colour 'Red' (expected red, green or blue)");
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

}  // namespace
}  // namespace shprt
