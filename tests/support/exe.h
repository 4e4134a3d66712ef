// The hdribr executable of the build, for the CLI tests (the test target defines HDRIBR_EXE).
#pragma once

#include <string>

namespace hdribr::test {

// The path of the build's hdribr executable.
inline std::string Exe() { return HDRIBR_EXE; }

}  // namespace hdribr::test
