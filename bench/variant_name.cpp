// The name of the hooks a study program is linked with ("solutions", "assignments", "reference"):
// this file is compiled once per variant, so that the study programs themselves are compiled once.
#include "report.h"

namespace gpl::study {

const char* const kHookVariant = GPL_VARIANT;

}  // namespace gpl::study
