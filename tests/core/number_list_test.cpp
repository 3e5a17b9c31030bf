#include "slamprep/core/number_list.hpp"

#include <gtest/gtest.h>

namespace slamprep {
namespace {

constexpr NumberListRule kSigned{-1.0, 1.0, 3, "a number in [-1, 1]"};

TEST(NumberList, ReadsCommaSeparatedNumbersUnderTheRule) {
  EXPECT_EQ(parseNumberList("", kSigned, nullptr)->size(), 0u);
  EXPECT_EQ(*parseNumberList("0.5,-1,1e-3", kSigned, nullptr),
            (std::vector<double>{0.5, -1.0, 0.001}));
  std::string why;
  EXPECT_FALSE(parseNumberList("0.5,1.5", kSigned, &why));
  EXPECT_EQ(why, "'1.5' is not a number in [-1, 1]");
  EXPECT_FALSE(parseNumberList("0.5,,0", kSigned, &why));
  EXPECT_EQ(why, "'' is not a number in [-1, 1]");
  EXPECT_FALSE(parseNumberList("nan", kSigned, &why));
  EXPECT_FALSE(parseNumberList("0.1 ", kSigned, &why));  // no trailing characters
  EXPECT_FALSE(parseNumberList("0,0,0,0", kSigned, &why));
  EXPECT_EQ(why, "more than 3 numbers");
}

}  // namespace
}  // namespace slamprep
