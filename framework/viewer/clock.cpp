#include "clock.h"

#include <cmath>

namespace gpl::viewer {

int FixedStepClock::advance(double realSeconds, double speed, double step, int maxSteps) {
    if (!(realSeconds > 0.0) || !(speed > 0.0) || !(step > 0.0)) return 0;
    banked_ += realSeconds * speed;
    const double wanted = std::floor(banked_ / step);
    if (wanted <= maxSteps) {
        banked_ -= wanted * step;
        return static_cast<int>(wanted);
    }
    dropped_ += (wanted - maxSteps) * step;
    banked_ -= wanted * step;
    return maxSteps;
}

}  // namespace gpl::viewer
