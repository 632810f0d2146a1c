// Prints every scene's key, name and viewSeconds, tab-separated, one scene a line: the seconds
// test_view_hints.py tracks each scene for, known before the viewer starts, so that each scene
// starts the viewer once.
#include <cstdio>

#include "gpl/scenes.h"

int main() {
    for (const gpl::Scene& s : gpl::scenes().all()) {
        std::printf("%s\t%s\t%.17g\n", s.key.c_str(), s.name.c_str(), s.viewSeconds);
    }
    return 0;
}
