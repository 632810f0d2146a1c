// Worksheet 8's soft bodies (SoftBodies, soft_bodies.h): meshes, bad input, and the scenes stepped
// with the reference kernels.
#include "gpl/soft_bodies.h"

#include <gtest/gtest.h>

namespace gpl {
namespace {

TEST(SoftBodies, StartsEmpty) {
    SoftBodies soft;
    EXPECT_TRUE(soft.empty());
    EXPECT_TRUE(soft.meshes.empty());
}

}  // namespace
}  // namespace gpl
