#include "gpl/body.h"
#include "gpl/contact.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace gpl {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(Body, SphereHasSolidSphereInertia) {
    const Body b = sphere("ball", 0.5, 2.0);
    EXPECT_DOUBLE_EQ(b.invMass, 0.5);
    EXPECT_TRUE(b.inertia.isApprox(Mat3::Identity() * 0.4 * 2.0 * 0.25));
    EXPECT_TRUE((b.inertia * b.invInertia).isApprox(Mat3::Identity()));
    EXPECT_FALSE(b.isStatic());
}

TEST(Body, BoxHasSolidBoxInertia) {
    const Body b = box("crate", {1.0, 2.0, 3.0}, 12.0);
    // I_xx = m (b^2 + c^2) / 12 with full side lengths b = 4, c = 6.
    EXPECT_DOUBLE_EQ(b.inertia(0, 0), 12.0 * (16.0 + 36.0) / 12.0);
    EXPECT_DOUBLE_EQ(b.inertia(1, 1), 12.0 * (4.0 + 36.0) / 12.0);
    EXPECT_DOUBLE_EQ(b.inertia(2, 2), 12.0 * (4.0 + 16.0) / 12.0);
}

TEST(Body, StaticMeansInverseMassZero) {
    const Body b = box("wall", {1.0, 1.0, 1.0}, 5.0).moving({1.0, 0.0, 0.0}).makeStatic();
    EXPECT_TRUE(b.isStatic());
    EXPECT_EQ(b.invMass, 0.0);
    EXPECT_TRUE(b.invInertia.isZero());
    EXPECT_TRUE(b.velocity.isZero());
    EXPECT_TRUE(plane("floor", {0.0, 2.0, 0.0}).isStatic());
    EXPECT_TRUE(plane("floor", {0.0, 2.0, 0.0}).normal.isApprox(Vec3::UnitY()));
}

TEST(Body, RejectsBadMassAndSize) {
    EXPECT_THROW(sphere("a", 0.5, -1.0), std::invalid_argument);
    EXPECT_THROW(sphere("a", 0.5, 0.0), std::invalid_argument);
    EXPECT_THROW(sphere("a", 0.5, kNaN), std::invalid_argument);
    EXPECT_THROW(sphere("a", -0.5, 1.0), std::invalid_argument);
    EXPECT_THROW(box("b", {1.0, 0.0, 1.0}, 1.0), std::invalid_argument);
    EXPECT_THROW(plane("p", Vec3::Zero()), std::invalid_argument);
    try {
        sphere("heavy", 0.5, -3.0);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("heavy"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("mass"), std::string::npos) << e.what();
    }
}

TEST(Body, ValidateNamesTheBadField) {
    Body b = sphere("ball", 0.5, 1.0);
    EXPECT_NO_THROW(validate(b));
    b.velocity.x() = kNaN;
    try {
        validate(b);
        FAIL() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("velocity"), std::string::npos) << e.what();
    }
    Body c = sphere("c", 0.5, 1.0);
    c.restitution = 1.5;
    EXPECT_THROW(validate(c), std::invalid_argument);
}

TEST(Body, FrictionCoefficientsChecked) {
    EXPECT_NO_THROW(validate(box("block", {0.1, 0.2, 0.3}, 1.0).rough(0.6, 0.4)));
    EXPECT_NO_THROW(validate(plane("ice", {0.0, 1.0, 0.0}).rough(0.0, 0.0)));
    const struct {
        double mus, mud;
        const char* field;
    } bad[] = {{kNaN, 0.4, "static friction"}, {0.6, kNaN, "friction"}, {-0.1, -0.2, "friction"},
               {0.6, -0.1, "friction"},      {0.3, 0.5, "below the sliding friction"},
               {std::numeric_limits<double>::infinity(), 0.5, "static friction"}};
    for (const auto& c : bad) {
        try {
            validate(box("block", {0.1, 0.2, 0.3}, 1.0).rough(c.mus, c.mud));
            FAIL() << "no exception for mu_s " << c.mus << ", mu_d " << c.mud;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(c.field), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("block"), std::string::npos) << e.what();
        }
    }
    // The pair's rule: the geometric mean keeps a material's own coefficient and mu_s >= mu_d.
    EXPECT_DOUBLE_EQ(combineFriction(0.4, 0.4), 0.4);
    EXPECT_EQ(combineFriction(0.0, 0.9), 0.0);
    EXPECT_GE(combineFriction(0.6, 0.9), combineFriction(0.5, 0.7));
}

TEST(Body, EnergyAndMomentum) {
    const Vec3 g(0.0, -9.81, 0.0);
    const Body b = sphere("ball", 1.0, 2.0).at({0.0, 3.0, 0.0}).moving({1.0, 2.0, 2.0}).spinning({0.0, 0.0, 2.0});
    // Translational 1/2 m v^2 = 9, rotational 1/2 (2/5 m r^2) w^2 = 1.6.
    EXPECT_DOUBLE_EQ(kineticEnergy(b), 9.0 + 1.6);
    EXPECT_DOUBLE_EQ(potentialEnergy(b, g), 2.0 * 9.81 * 3.0);
    EXPECT_TRUE(linearMomentum(b).isApprox(Vec3(2.0, 4.0, 4.0)));
    const Body wall = box("wall", {1.0, 1.0, 1.0}, 1.0).at({0.0, 3.0, 0.0}).makeStatic();
    EXPECT_EQ(kineticEnergy(wall), 0.0);
    EXPECT_EQ(potentialEnergy(wall, g), 0.0);
}

}  // namespace
}  // namespace gpl
