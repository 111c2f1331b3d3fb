#pragma once
// Runs the rbaa program as a user would and captures its exit code, stdout and stderr.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

namespace rbaa_cli_test {

struct Result {
  int exit_code;
  std::string out;  // stdout
  std::string err;  // stderr
};

/// A ~300-tet ball meeting a wall at 2 m/s without gravity: five steps of 0.01 s.
inline const char* const kTinyBall =
    "mesh: {shape: sphere, radius: 0.1, target_tets: 300}\n"
    "object: {position: [0, -0.13, 0.5], velocity: [0, 2.0, 0]}\n"
    "obstacles: {planes: [{normal: [0, -1, 0], offset: 0}]}\n"
    "gravity: off\n"
    "time: {step: 0.01, duration: 0.05}\n";

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(::testing::TempDir()) / ("rbaa_cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  /// Runs a shell command and returns its exit code and stdout.
  static Result shell(const std::string& command) {
    Result r{0, "", ""};
    FILE* pipe = popen(command.c_str(), "r");
    char buffer[4096];
    while (size_t n = fread(buffer, 1, sizeof(buffer), pipe)) r.out.append(buffer, n);
    const int status = pclose(pipe);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
  }

  /// Runs rbaa with `args`; stderr in Result::err.
  Result run(const std::string& args) {
    const std::string err_file = (dir_ / "stderr.txt").string();
    Result r = shell(std::string(RBAA_EXECUTABLE) + " " + args + " 2>" + err_file);
    std::ifstream in(err_file);
    std::stringstream ss;
    ss << in.rdbuf();
    r.err = ss.str();
    return r;
  }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// Writes `text` to `name` in the test's folder and returns its path.
  std::string write_file(const std::string& name, const std::string& text) {
    std::ofstream(path(name)) << text;
    return path(name);
  }

  /// The report.json a verb wrote to `dir` (a folder in the test's folder, as given to path()).
  nlohmann::json report(const std::string& dir) const {
    std::ifstream in(path(dir + "/report.json"));
    return nlohmann::json::parse(in);
  }

  static std::string slurp(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  // A failing command: non-zero exit, and one error line (the last on stderr; progress lines
  // may come before it) naming what is wrong.
  void expect_failure(const std::string& args, const std::string& fragment) {
    const Result r = run(args);
    EXPECT_NE(r.exit_code, 0) << args;
    std::string last;
    int error_lines = 0;
    std::istringstream lines(r.err);
    for (std::string line; std::getline(lines, line);) {
      last = line;
      error_lines += line.find("error") != std::string::npos;
    }
    EXPECT_NE(last.find(fragment), std::string::npos) << r.err;
    EXPECT_EQ(error_lines, 1) << r.err;
  }

  std::filesystem::path dir_;
};

}  // namespace rbaa_cli_test
