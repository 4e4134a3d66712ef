// Error handling: typed exceptions for bad input, CHECK for programmer invariants.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace hdribr {

// Bad user input (file missing, corrupt, inconsistent). Caught in main: one line, non-zero exit.
class InputError : public std::runtime_error {
 public:
  InputError(const std::filesystem::path& file, const std::string& problem);
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// Invalid argument on the command line or in an API call made with user-provided values.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An option value no computation can use. `field` names the member of the options struct, so
// that a front end can name its own spelling of the option; what() is "<field> <problem>".
class OptionError : public UsageError {
 public:
  OptionError(const std::string& field, const std::string& problem);
  const std::string& field() const { return field_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string field_;
  std::string problem_;
};

[[noreturn]] void CheckFailed(const char* file, int line, const char* expr, const std::string& msg);

}  // namespace hdribr

// Aborts with file:line when a programmer invariant is violated (never for user input).
#define HDRIBR_CHECK(cond)                                             \
  do {                                                                 \
    if (!(cond)) ::hdribr::CheckFailed(__FILE__, __LINE__, #cond, ""); \
  } while (0)
#define HDRIBR_CHECK_MSG(cond, msg)                                     \
  do {                                                                  \
    if (!(cond)) ::hdribr::CheckFailed(__FILE__, __LINE__, #cond, msg); \
  } while (0)
