// Built instead of bullet_heap.cpp when Bullet is not installed: the lab builds and its tests pass
// without it; `./lab bench engine` installs libbullet-dev and builds the comparison.
#include <stdexcept>

#include "heap.h"

namespace gpl::bench {

bool hasBullet() { return false; }

std::unique_ptr<HeapSim> bulletHeap(HeapShape, std::size_t) {
    throw std::runtime_error("built without Bullet (Debian libbullet-dev): ./lab bench engine installs it");
}

}  // namespace gpl::bench
