#pragma once
// One row of a sweep on disk and as a process: its folder DIR/row-NNN holds the verb's outputs,
// log.txt (the row's stdout and stderr) and sweep_row.json, the row's marker: its arguments and
// status and the config's fingerprint (config_fingerprint.hpp), written atomically when the row
// starts and when it ends. A row whose marker says "ok" with the same arguments and fingerprint is
// finished and is skipped when the sweep runs again.

#include <string>
#include <vector>

namespace rbaa {

enum class RowStatus {
  kPending,  ///< never started (no marker)
  kRunning,  ///< started and not finished: running now, or its process was killed
  kOk,       ///< the verb exited 0
  kFailed,   ///< the verb exited non-zero or was killed; `error` says why
};

/// "pending", "running", "ok", "failed".
const char* status_name(RowStatus status);

struct RowOutcome {
  int index = 0;
  RowStatus status = RowStatus::kPending;
  std::vector<std::string> arguments;  ///< the row's command line (row_arguments)
  std::string error;                   ///< one line, for a failed row
  int exit_code = 0;
  double seconds = 0;  ///< wall time of the row's process
  /// config_fingerprint of the grid when the row started; "" in markers written before the
  /// sweep kept one (those cannot be checked).
  std::string config_fingerprint;
};

/// The marker in `row_dir`; status kPending when there is none. Throws InputError naming the file
/// if it exists but cannot be read.
RowOutcome read_row_outcome(const std::string& row_dir, int index);

/// Writes the marker atomically (creating `row_dir`).
void write_row_outcome(const std::string& row_dir, const RowOutcome& outcome);

/// Starts `executable arguments... --out=row_dir` with stdout and stderr written to
/// row_dir/log.txt, OMP_NUM_THREADS=threads and OPENBLAS_NUM_THREADS=1 (unless set in this
/// process's environment); returns the child's pid. Throws if fork fails.
int start_row_process(const std::string& executable, const std::vector<std::string>& arguments,
                      const std::string& row_dir, int threads);

/// The row's one-line error after its process ended with `wait_status` (from waitpid): the last
/// line of its log that says "error", else its last line, with the exit code or signal.
std::string row_error(const std::string& row_dir, int wait_status);

}  // namespace rbaa
