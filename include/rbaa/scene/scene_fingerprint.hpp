#pragma once
// What identifies an attack run, for --resume: a hash over the parsed scene's settings that change
// the attack's result, not over the config file's bytes. Comments, key order, number spelling
// (1e13 or 1.0e+13), the config's name and path, the evaluation's settings and the settings that
// only bound or extend the work (attack.iterations, attack.polish_iterations,
// newton.max_iterations) leave it unchanged; a mesh or surface file enters by its content.
//
// A field added to Scene that changes an attack's result must be added to scene_fingerprint
// (test Scene.FingerprintSeesEverySettingThatChangesAResult lists them).

#include <string>

#include "rbaa/scene/scene.hpp"

namespace rbaa {

/// 16 hex digits (FNV-1a, 64 bit) over a canonical text of the result-changing settings.
std::string scene_fingerprint(const Scene& scene);

/// 16 hex digits of FNV-1a (64 bit) over `bytes`: the hash of every fingerprint (stable across
/// builds and machines, unlike std::hash, since checkpoints and sweep markers outlive builds).
std::string fingerprint_hex(const std::string& bytes);

/// The canonical text itself (one "key value" line per setting, doubles as hex floats), for
/// diagnosis and tests.
std::string scene_fingerprint_text(const Scene& scene);

}  // namespace rbaa
