#include "rbaa/sweep/slurm_script.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"

namespace rbaa {
namespace {

namespace fs = std::filesystem;

// Single-quoted for the shell.
std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string sbatch_header(const SweepGrid& grid, const SlurmJob& job, const std::string& name,
                          const std::string& output) {
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# Written by `rbaa sweep --emit=slurm` for " << job.grid << " (" << grid.rows.size()
    << " rows of `rbaa " << grid.verb << "`); submit with: bash " << job.out_dir
    << "/slurm/submit.sh\n"
    << "#SBATCH --job-name=" << name << "\n"
    << "#SBATCH --output=" << output << "\n"
    << "#SBATCH --chdir=" << job.workdir << "\n";
  bool cpus = false;
  for (const auto& [key, value] : grid.slurm_options) {
    s << "#SBATCH --" << key << "=" << value << "\n";
    cpus = cpus || key == "cpus-per-task";
  }
  if (!cpus) s << "#SBATCH --cpus-per-task=1\n";
  return s.str();
}

}  // namespace

SlurmScripts slurm_scripts(const SweepGrid& grid, const SlurmJob& job) {
  if (grid.rows.empty()) throw InputError(grid.source + ": no rows");
  const std::string name = "rbaa-sweep-" + fs::path(job.grid).stem().string();
  const std::string common = quoted(job.executable) + " sweep --grid=" + quoted(job.grid) +
                             " --out=" + quoted(job.out_dir);
  SlurmScripts s;
  {
    std::ostringstream a;
    a << sbatch_header(grid, job, name, job.out_dir + "/slurm/row-%a.out");
    a << "#SBATCH --array=0-" << grid.rows.size() - 1;
    if (job.max_parallel > 0) a << "%" << job.max_parallel;
    a << "\n\n"
      << "# One row per task, in " << job.out_dir << "/row-NNN; a finished row is skipped, so the\n"
      << "# array can be submitted again after a failure. Threads: the task's CPUs "
         "(--cpus-per-task).\n"
      << "exec " << common << " --row=\"$SLURM_ARRAY_TASK_ID\"\n";
    s.array = a.str();
  }
  {
    std::ostringstream m;
    m << sbatch_header(grid, job, name + "-merge", job.out_dir + "/slurm/merge.out") << "\n"
      << "# After the whole array (submit.sh adds --dependency=afterany:ARRAY): gathers every "
         "row's\n"
      << "# status and report into " << job.out_dir << "/results.csv.\n"
      << "exec " << common << " --merge\n";
    s.merge = m.str();
  }
  {
    std::ostringstream u;
    const std::string dir = job.out_dir + "/slurm";
    u << "#!/bin/bash\n"
      << "# Submits the sweep's array and its merge job (afterany: it runs even if rows fail).\n"
      << "set -euo pipefail\n"
      << "array=$(sbatch --parsable " << quoted(dir + "/array.sbatch") << ")\n"
      << "array=${array%%;*}\n"
      << "merge=$(sbatch --parsable --dependency=afterany:\"$array\" "
      << quoted(dir + "/merge.sbatch") << ")\n"
      << "merge=${merge%%;*}\n"
      << "echo \"array job $array (" << grid.rows.size() << " tasks), merge job $merge -> "
      << job.out_dir << "/results.csv\"\n";
    s.submit = u.str();
  }
  return s;
}

std::string write_slurm_scripts(const SweepGrid& grid, const SlurmJob& job) {
  const SlurmScripts s = slurm_scripts(grid, job);
  const fs::path dir = fs::path(job.out_dir) / "slurm";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir.string() + ": cannot create folder (" + ec.message() + ")");
  for (const auto& [name, text] :
       {std::pair<const char*, const std::string*>{"array.sbatch", &s.array},
        {"merge.sbatch", &s.merge},
        {"submit.sh", &s.submit}}) {
    const std::string path = (dir / name).string();
    write_file_atomically(path, [&](std::ostream& out) { out << *text; });
    ::chmod(path.c_str(), 0755);
  }
  return (dir / "submit.sh").string();
}

}  // namespace rbaa
