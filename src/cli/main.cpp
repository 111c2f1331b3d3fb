// rbaa's command line: `rbaa <verb> --flags`. Flags are gflags (so --flagfile works); each verb
// lives in src/cli/verb_<name>.cpp. Errors from the library are caught here once, printed on one
// line, and turned into a non-zero exit code.

#include <gflags/gflags.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "rbaa/cli/verb.hpp"
#include "rbaa/error.hpp"
#include "rbaa/sim/threads.hpp"

namespace {

void print_overview() {
  std::cout << "rbaa: rigid body adversarial attacks\n\n"
               "usage: rbaa <verb> [--flags]      rbaa <verb> --help\n\nverbs:\n";
  for (const auto& verb : rbaa::cli::registered_verbs()) {
    std::cout << "  " << verb.name << std::string(12 - std::min<size_t>(11, verb.name.size()), ' ')
              << verb.summary << "\n";
  }
  std::cout << "\nCommon flags: --flagfile=FILE, --v=N (verbose logging), --logtostderr.\n";
}

void print_verb_help(const rbaa::cli::Verb& verb) {
  std::cout << "usage: " << verb.usage << "\n\nflags:\n";
  for (const auto& name : verb.flags) {
    gflags::CommandLineFlagInfo info;
    if (!gflags::GetCommandLineFlagInfo(name.c_str(), &info)) continue;
    std::cout << "  --" << info.name << " (" << info.type << ", default \"" << info.default_value
              << "\")\n      " << info.description << "\n";
  }
}

/// gflags keeps only the last value of a repeated flag, so `--set=a=1 --set=b=2` would silently
/// drop `a=1`. Repeated `--set` (as `--set=V`, `-set=V` or `--set V`) are merged here, in order,
/// into one `--set=V1;V2` at the first one's place, as users of such flags expect. A `--set` read
/// from a --flagfile is gflags' own: the last one given wins there.
void merge_set_flags(std::vector<char*>& args, std::string& storage) {
  std::vector<std::string> values;
  size_t first = 0;
  for (size_t i = 1; i < args.size();) {
    const std::string arg = args[i];
    std::string value;
    size_t taken = 0;
    for (const char* prefix : {"--set=", "-set="}) {
      if (arg.rfind(prefix, 0) == 0) {
        value = arg.substr(std::strlen(prefix));
        taken = 1;
      }
    }
    if (!taken && (arg == "--set" || arg == "-set") && i + 1 < args.size()) {
      value = args[i + 1];
      taken = 2;
    }
    if (!taken) {
      ++i;
      continue;
    }
    if (values.empty()) first = i;
    values.push_back(value);
    args.erase(args.begin() + static_cast<std::ptrdiff_t>(i),
               args.begin() + static_cast<std::ptrdiff_t>(i + taken));
  }
  if (values.empty()) return;
  storage = "--set=";
  for (size_t k = 0; k < values.size(); ++k) storage += (k ? ";" : "") + values[k];
  args.insert(args.begin() + static_cast<std::ptrdiff_t>(first), storage.data());
}

/// Why the flags given on the command line (or in a --flagfile) do not fit `verb`, or "": every
/// flag given must be one the verb reads (verb_reads_flag), and a number must be finite (gflags
/// reads inf and nan as doubles).
std::string unfit_flags(const rbaa::cli::Verb& verb) {
  std::vector<gflags::CommandLineFlagInfo> all;
  gflags::GetAllFlags(&all);
  for (const auto& info : all) {
    if (info.is_default) continue;
    if (!rbaa::cli::verb_reads_flag(verb, info.name, info.filename)) {
      return "--" + info.name + " is not a flag of rbaa " + verb.name + " (rbaa " + verb.name +
             " --help lists its flags)";
    }
    if (info.type == "double" && !std::isfinite(std::strtod(info.current_value.c_str(), nullptr))) {
      return "--" + info.name + "=" + info.current_value + ": expected a finite number";
    }
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  FLAGS_logtostderr = true;
  rbaa::tune_threads_for_shared_cores();
  google::InitGoogleLogging(argv[0]);
  gflags::SetUsageMessage("rbaa <verb> [--flags]; rbaa --help lists the verbs");

  std::vector<char*> args(argv, argv + argc);
  std::string verb_name;
  if (args.size() > 1 && args[1][0] != '-') {
    verb_name = args[1];
    args.erase(args.begin() + 1);
  }
  bool help = false;
  for (auto it = args.begin() + 1; it != args.end();) {
    if (!std::strcmp(*it, "--help") || !std::strcmp(*it, "-h") || !std::strcmp(*it, "-help")) {
      help = true;
      it = args.erase(it);
    } else {
      ++it;
    }
  }
  std::string merged_set;
  merge_set_flags(args, merged_set);
  int new_argc = static_cast<int>(args.size());
  char** new_argv = args.data();
  gflags::ParseCommandLineFlags(&new_argc, &new_argv, true);
  if (new_argc > 1) {
    std::cerr << "rbaa: error: unexpected argument '" << new_argv[1] << "' (see rbaa --help)\n";
    return 2;
  }

  if (verb_name.empty()) {
    print_overview();
    return help ? 0 : 2;
  }
  for (const auto& verb : rbaa::cli::registered_verbs()) {
    if (verb.name != verb_name) continue;
    if (help) {
      print_verb_help(verb);
      return 0;
    }
    if (const std::string unfit = unfit_flags(verb); !unfit.empty()) {
      std::cerr << "rbaa " << verb_name << ": error: " << unfit << "\n";
      return 2;
    }
    try {
      return verb.run();
    } catch (const rbaa::InputError& e) {
      std::cerr << "rbaa " << verb_name << ": error: " << e.what() << "\n";
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "rbaa " << verb_name << ": error: " << e.what() << "\n";
      return 1;
    }
  }
  std::cerr << "rbaa: error: unknown verb '" << verb_name << "' (see rbaa --help)\n";
  return 2;
}
