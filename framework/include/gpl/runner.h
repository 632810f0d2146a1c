// Headless runner: steps a loaded scene, optionally writes one CSV row per body and step, and
// summarises the run (energy drift, hooks still open).
#pragma once

#include <cstddef>
#include <ostream>
#include <string>

#include "gpl/engine.h"

namespace gpl {

struct RunSummary {
    std::size_t steps = 0;           ///< steps taken
    double simulatedTime = 0.0;      ///< s
    double initialEnergy = 0.0;      ///< J
    double finalEnergy = 0.0;        ///< J
    double maxEnergyIncrease = 0.0;  ///< largest increase of the total energy over one step (J), 0 if none
    double maxSpeed = 0.0;           ///< largest speed of any body or particle at the end (m/s)
    std::size_t maxContacts = 0;     ///< most contacts found in one step
    double deepestContact = 0.0;     ///< largest depth of any contact found, before resolution (m)
    std::string error;               ///< empty, or why the run stopped early (a non-finite state)

    // The world's angular momentum about the origin (kg m^2/s), shown in scenes that rotate.
    Vec3 initialAngularMomentum = Vec3::Zero();
    Vec3 finalAngularMomentum = Vec3::Zero();  ///< at the end

    // Soft bodies (worksheet 8), over every state of the run (the start's and each step's end),
    // shown in scenes that have them.
    double largestStretch = 0.0;          ///< largest relative stretch of a cloth's grid edge, a rope or a soft body's edge
    double smallestVolumeRatio = 1.0;     ///< of any soft body: its volume over its rest volume
    double largestVolumeRatio = 1.0;
    double deepestPenetration = 0.0;      ///< m, the deepest a particle's sphere lay inside a rigid body
};

/// The CSV header written by run(): step,time,body,x,y,z,vx,vy,vz,kinetic,potential,total.
/// One row per body and step (step 0 is the initial state); a row named "world" holds the centre
/// of mass, its velocity and the world's energies.
void writeCsvHeader(std::ostream& csv);

/// Steps the engine `steps` times. Rows go to csv when it is not null, flushed after every step. A
/// SimulationError stops the run and is reported in the summary instead of thrown; the summary's
/// end (energy, speed, time) is the last state that was finite.
RunSummary run(PhysicsEngine& engine, std::size_t steps, std::ostream* csv);

/// The step run() is taking now (1 for the first of the engine), 0 outside run(); safe to read
/// in a signal handler (the runner's, when a failed assertion aborts a step).
std::size_t stepInProgress();

/// The summary as a few lines of text for people: why the run stopped first, if it did, then
/// the steps that ended finite.
std::string describe(const RunSummary& summary, const PhysicsEngine& engine);

}  // namespace gpl
