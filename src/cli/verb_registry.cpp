#include <algorithm>

#include "rbaa/cli/verb.hpp"

namespace rbaa::cli {
namespace {

std::vector<Verb>& registry() {
  static std::vector<Verb> verbs;
  return verbs;
}

}  // namespace

bool register_verb(Verb verb) {
  registry().push_back(std::move(verb));
  return true;
}

std::vector<Verb> registered_verbs() {
  std::vector<Verb> verbs = registry();
  std::sort(verbs.begin(), verbs.end(), [](const Verb& a, const Verb& b) { return a.name < b.name; });
  return verbs;
}

}  // namespace rbaa::cli
