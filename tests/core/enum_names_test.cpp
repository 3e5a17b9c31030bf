#include "slamprep/core/enum_names.hpp"

#include <gtest/gtest.h>

namespace slamprep {
namespace {

enum class Colour { kRed, kGreen, kBlue };
constexpr auto kColourNames = std::to_array<EnumName<Colour>>({
    {Colour::kRed, "red"},
    {Colour::kGreen, "green"},
    {Colour::kBlue, "blue"},
});

TEST(EnumNames, NameAndFindAreInverse) {
  for (const auto& [value, name] : kColourNames) {
    EXPECT_EQ(nameOf(kColourNames, value), name);
    EXPECT_EQ(findName(kColourNames, name), value);
  }
  static_assert(nameOf(kColourNames, Colour::kGreen) == "green");
  static_assert(findName(kColourNames, "blue") == Colour::kBlue);
}

TEST(EnumNames, UnknownValuesAndNames) {
  EXPECT_EQ(nameOf(kColourNames, static_cast<Colour>(7)), "unknown");
  EXPECT_FALSE(findName(kColourNames, "Red"));  // names are case-sensitive
  EXPECT_FALSE(findName(kColourNames, ""));
  EXPECT_FALSE(findName(kColourNames, "re"));
}

TEST(EnumNames, NamesInTableOrder) {
  EXPECT_EQ(namesOf(kColourNames), (std::vector<std::string>{"red", "green", "blue"}));
  EXPECT_EQ(joinedNames(kColourNames, "|"), "red|green|blue");
}

TEST(EnumNames, ParseThrowsNamingWhereTheTextAndTheValidNames) {
  EXPECT_EQ(parseName(kColourNames, "blue", "colour", "--colour"), Colour::kBlue);
  try {
    parseName(kColourNames, "purple", "colour", "--colour");
    FAIL() << "accepted an unknown name";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--colour: unknown colour 'purple' (valid: red, green, blue)");
  }
}

}  // namespace
}  // namespace slamprep
