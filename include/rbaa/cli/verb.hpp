#pragma once
// The command line's verbs. Each verb lives in its own file src/cli/verb_<name>.cpp and registers
// itself with RBAA_REGISTER_VERB; main() dispatches on argv[1], after gflags has parsed the flags.

#include <algorithm>
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

/// Whether `verb` reads the flag `name` defined in the source file `defined_in` (gflags'
/// CommandLineFlagInfo name and filename): rbaa's own flags (defined under cli/) when the verb
/// lists them, glog's and gflags' own (--v, --logtostderr, --flagfile) always. gflags' registry
/// is global, so a flag it knows may be another verb's, which this verb would accept and ignore.
/// main() checks the command line with it, rbaa sweep a grid's flags:.
inline bool verb_reads_flag(const Verb& verb, const std::string& name,
                            const std::string& defined_in) {
  if (defined_in.find("cli/") == std::string::npos) return true;
  return std::find(verb.flags.begin(), verb.flags.end(), name) != verb.flags.end();
}

/// Adds a verb to the registry (called from static initialisers).
bool register_verb(Verb verb);

/// All registered verbs, sorted by name.
std::vector<Verb> registered_verbs();

}  // namespace rbaa::cli

#define RBAA_REGISTER_VERB(ident, ...) \
  static const bool rbaa_verb_registered_##ident = ::rbaa::cli::register_verb(__VA_ARGS__)
