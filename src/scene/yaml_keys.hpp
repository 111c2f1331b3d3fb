#pragma once
// Internal (not installed: yaml-cpp is a private dependency): the check of a YAML document's keys
// that the config reader and the sweep's grid reader share.

#include <yaml-cpp/yaml.h>

#include <string>

namespace rbaa {

/// Every key of every mapping in `node` a name, and none twice: yaml-cpp keeps both entries of a
/// repeated key and every read finds the first, so `time: {step: 0.01, step: 0.002}` (or a
/// second `time:` block) would silently lose the later value. Throws rbaa::InputError
/// "SOURCE[:LINE]: key 'a.b' is given twice in this mapping (...)" or "... a key must be a name";
/// `lines`: name the line (a --set value has none of its own).
void check_keys(const YAML::Node& node, const std::string& source, const std::string& prefix,
                bool lines = true);

}  // namespace rbaa
