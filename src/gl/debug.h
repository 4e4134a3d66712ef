// GL_KHR_debug output and error checks.
#pragma once

#include <string>

namespace hdribr::gl {

// In debug builds (NDEBUG undefined) or when HDRIBR_GL_DEBUG=1 is set, installs a
// GL_KHR_debug callback that logs errors and warnings (spdlog) and counts errors.
void InstallDebugCallback();
// Number of GL errors reported by the debug callback since the context was made.
int DebugErrorCount();
// Empty when glGetError() reports no error, else the error names ("GL_INVALID_VALUE ...").
std::string DrainGlErrors();

}  // namespace hdribr::gl
