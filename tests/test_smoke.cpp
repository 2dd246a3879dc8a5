#include <gtest/gtest.h>
#include "trace.h"
TEST(Smoke, Builds) { EXPECT_EQ(pack_color(v3(1, 0, 0)), 0xffff0000u); }
