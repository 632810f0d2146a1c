// Fixed physics step with an accumulator: real time (times the speed) is banked and spent in
// whole steps, so no time is lost when rendering is slow. At most maxSteps are taken per frame;
// time beyond that is dropped and counted (no spiral of death) instead of piling up.
#pragma once

namespace gpl::viewer {

class FixedStepClock {
public:
    /// Banks realSeconds * speed of simulated time and returns how many steps of `step` seconds
    /// to take now (0 .. maxSteps).
    int advance(double realSeconds, double speed, double step, int maxSteps);
    double banked() const { return banked_; }    ///< s of simulated time not stepped yet (< step)
    double dropped() const { return dropped_; }  ///< s of simulated time dropped so far
    void reset() { banked_ = dropped_ = 0.0; }

private:
    double banked_ = 0.0;
    double dropped_ = 0.0;
};

}  // namespace gpl::viewer
