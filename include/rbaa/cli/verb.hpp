#pragma once
// The command line's verbs. Each verb lives in its own file src/cli/verb_<name>.cpp and registers
// itself with RBAA_REGISTER_VERB; main() dispatches on argv[1], after gflags has parsed the flags.

#include <functional>
#include <string>
#include <vector>

namespace rbaa::cli {

struct Verb {
  std::string name;
  std::string summary;                 ///< one line for `rbaa --help`
  std::string usage;                   ///< the verb's synopsis and description for `rbaa VERB --help`
  std::vector<std::string> flags;      ///< names of the gflags the verb reads (listed in its help)
  std::function<int()> run;            ///< runs the verb; throws on bad input; returns the exit code
};

/// Adds a verb to the registry (called from static initialisers).
bool register_verb(Verb verb);

/// All registered verbs, sorted by name.
std::vector<Verb> registered_verbs();

}  // namespace rbaa::cli

#define RBAA_REGISTER_VERB(ident, ...) \
  static const bool rbaa_verb_registered_##ident = ::rbaa::cli::register_verb(__VA_ARGS__)
