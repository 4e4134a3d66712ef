#include "core/error.h"

#include <cstdio>
#include <cstdlib>

namespace hdribr {

InputError::InputError(const std::filesystem::path& file, const std::string& problem)
    : std::runtime_error(file.string() + ": " + problem) {}

OptionError::OptionError(const std::string& field, const std::string& problem)
    : UsageError(field + " " + problem), field_(field), problem_(problem) {}

void CheckFailed(const char* file, int line, const char* expr, const std::string& msg) {
  std::fprintf(stderr, "%s:%d: check failed: %s %s\n", file, line, expr, msg.c_str());
  std::abort();
}

}  // namespace hdribr
