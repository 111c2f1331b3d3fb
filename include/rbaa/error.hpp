#pragma once
// Library errors. The library throws; the command line catches once, prints the message on one
// line and exits non-zero. Messages name the input at fault (file, line, key or value).

#include <stdexcept>
#include <string>

namespace rbaa {

/// Bad input: unreadable or malformed files, invalid meshes, bad config values.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A computation that failed (e.g. Newton did not converge); the message names the step.
class SolverError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rbaa
