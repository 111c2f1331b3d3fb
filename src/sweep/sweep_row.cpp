#include "rbaa/sweep/sweep_row.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <system_error>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"

extern char** environ;

namespace rbaa {
namespace {

namespace fs = std::filesystem;

const char* const kMarker = "sweep_row.json";
const char* const kLog = "log.txt";

RowStatus status_from(const std::string& name, const std::string& file) {
  for (RowStatus s :
       {RowStatus::kPending, RowStatus::kRunning, RowStatus::kOk, RowStatus::kFailed}) {
    if (name == status_name(s)) return s;
  }
  throw InputError(file + ": unknown status '" + name + "'");
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

}  // namespace

const char* status_name(RowStatus status) {
  switch (status) {
    case RowStatus::kPending:
      return "pending";
    case RowStatus::kRunning:
      return "running";
    case RowStatus::kOk:
      return "ok";
    case RowStatus::kFailed:
      return "failed";
  }
  return "?";
}

RowOutcome read_row_outcome(const std::string& row_dir, int index) {
  RowOutcome r;
  r.index = index;
  const std::string file = (fs::path(row_dir) / kMarker).string();
  std::ifstream in(file);
  if (!in) return r;
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    r.status = status_from(j.at("status").get<std::string>(), file);
    r.arguments = j.at("arguments").get<std::vector<std::string>>();
    r.error = j.value("error", "");
    r.exit_code = j.value("exit_code", 0);
    r.seconds = j.value("seconds", 0.0);
    r.config_fingerprint = j.value("config_fingerprint", "");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file + ": unreadable sweep row marker (" + e.what() + ")");
  }
  return r;
}

void write_row_outcome(const std::string& row_dir, const RowOutcome& r) {
  std::error_code ec;
  fs::create_directories(row_dir, ec);
  if (ec) throw InputError(row_dir + ": cannot create the row's folder (" + ec.message() + ")");
  const nlohmann::json j = {
      {"row", r.index},           {"status", status_name(r.status)},
      {"arguments", r.arguments}, {"config_fingerprint", r.config_fingerprint},
      {"error", r.error},         {"exit_code", r.exit_code},
      {"seconds", r.seconds}};
  write_file_atomically((fs::path(row_dir) / kMarker).string(),
                        [&](std::ostream& out) { out << j.dump(2) << "\n"; });
}

int start_row_process(const std::string& executable, const std::vector<std::string>& arguments,
                      const std::string& row_dir, int threads) {
  std::error_code ec;
  fs::create_directories(row_dir, ec);
  if (ec) throw InputError(row_dir + ": cannot create the row's folder (" + ec.message() + ")");
  // Everything the child needs is built before fork: after it, only async-signal-safe calls.
  std::vector<std::string> argv_text = {executable};
  argv_text.insert(argv_text.end(), arguments.begin(), arguments.end());
  argv_text.push_back("--out=" + row_dir);
  std::vector<char*> argv;
  for (auto& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);

  std::vector<std::string> env_text;
  for (char** e = environ; *e; ++e) {
    if (std::strncmp(*e, "OMP_NUM_THREADS=", 16) != 0) env_text.emplace_back(*e);
  }
  env_text.push_back("OMP_NUM_THREADS=" + std::to_string(threads));
  // OpenBLAS beside OpenMP is slower on more than one thread (sim/threads.hpp); the user's
  // setting wins.
  if (!std::getenv("OPENBLAS_NUM_THREADS")) env_text.push_back("OPENBLAS_NUM_THREADS=1");
  std::vector<char*> envp;
  for (auto& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);

  const std::string log = (fs::path(row_dir) / kLog).string();
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(log + ": cannot open the row's log (" + std::strerror(errno) + ")");
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fd);
    throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
  }
  if (pid == 0) {
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    ::execve(argv[0], argv.data(), envp.data());
    static const char msg[] = "rbaa sweep: error: cannot start the row's program\n";
    (void)!::write(2, msg, sizeof(msg) - 1);
    ::_exit(127);
  }
  ::close(fd);
  return pid;
}

std::string row_error(const std::string& row_dir, int wait_status) {
  std::ifstream in(fs::path(row_dir) / kLog);
  std::string last, last_error;
  for (std::string line; std::getline(in, line);) {
    line = trim(line);
    if (line.empty()) continue;
    last = line;
    if (line.find("error") != std::string::npos) last_error = line;
  }
  std::string said = !last_error.empty() ? last_error : last;
  std::string how;
  if (WIFSIGNALED(wait_status)) {
    how = "killed by signal " + std::to_string(WTERMSIG(wait_status)) + " (" +
          strsignal(WTERMSIG(wait_status)) + ")";
  } else if (WIFEXITED(wait_status)) {
    how = "exit code " + std::to_string(WEXITSTATUS(wait_status));
  }
  if (said.size() > 400) said = said.substr(0, 400) + "...";
  return said.empty() ? how : said + " [" + how + "]";
}

}  // namespace rbaa
