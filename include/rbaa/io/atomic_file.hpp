#pragma once
// Every file rbaa writes goes through write_file_atomically: a crash, a full disk or Ctrl-C in
// the middle of a write leaves either the old file or the new one, never half of one (SPEC 8:
// nothing a long run has computed is lost).

#include <functional>
#include <ostream>
#include <string>

namespace rbaa {

/// Calls `writer` on a stream to PATH.tmp.<pid> in the same directory, flushes and fsyncs it,
/// then renames it over `path`. The stream uses the classic locale. On any failure (directory
/// missing or not writable, disk full, `writer` throwing) the temporary file is removed and
/// InputError naming `path` is thrown (the writer's own exception is rethrown unchanged).
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& writer);

}  // namespace rbaa
