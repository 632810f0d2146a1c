// A build without solutions/ (a student release not written with --reference-demo) has no reference ghost.
#include "reference.h"

namespace gplref {

std::unique_ptr<ReferenceWorld> makeReferenceWorld() { return nullptr; }

}  // namespace gplref
