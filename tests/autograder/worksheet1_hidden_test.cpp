// Worksheet 1, hidden tests: graded by instructors and on Gradescope, left out of student releases
// (./lab release drops every file that declares a hidden test; such a file holds hidden tests only).
#include <cmath>
#include <string>

#include "gpl/engine.h"
#include "graded.h"

namespace gpl {
namespace {

class Worksheet1Hidden : public ::testing::Test {
protected:
    PhysicsEngine engine;
};

GRADED_TEST(Worksheet1Hidden, EnergyLossPerStepIsExact, 2,
            "Semi-implicit Euler under constant gravity removes exactly m g^2 h^2 / 2 of energy per step: "
            "v += h a, then x += h v with the new velocity, nothing else.",
            grading::dependsOn("Worksheet1.OneStepIsSemiImplicitEuler"), grading::hidden()) {
    // One step from (x, v): kinetic energy changes by m h g.v + m h^2 g^2 / 2, potential energy
    // -m g.x by -m h g.v - m h^2 g^2, so the total by -m g^2 h^2 / 2 whatever x and v are.
    const double m = 2.5, h = 0.02;
    engine.setTimeStep(h);
    engine.add(sphere("ball", 0.2, m).at({0.0, 30.0, 0.0}).moving({3.0, 12.0, -1.0}));
    const double g2 = engine.gravity().squaredNorm();
    const double expected = -0.5 * m * g2 * h * h;
    for (int i = 1; i <= 400; ++i) {
        const double before = engine.totalEnergy();
        engine.step();
        const double change = engine.totalEnergy() - before;
        // The energies are sums of terms up to ~1e3 J: rounding leaves ~1e-12 of them, far below
        // the expected change of 5e-3 J per step.
        ASSERT_NEAR(change, expected, 1e-8) << "energy change in step " << i << " (expected -m g^2 h^2 / 2)";
    }
}

}  // namespace
}  // namespace gpl
