#pragma once
// Shared by the io tests: a scratch directory per test and a small but irregular tet mesh whose
// coordinates have no short decimal form, so exact round trips are a real check.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "rbaa/error.hpp"
#include "rbaa/mesh/tet_mesh.hpp"

namespace rbaa::test {

/// A fresh directory for the running test, removed when the object goes.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    // A parameterised test's suite and test names hold slashes ("Versions/MshRoundTrip",
    // "Reads/2"): one folder, not a nested one whose parent would be left behind.
    std::string name = "rbaa_io_test_" + std::to_string(::getpid()) + "_" +
                       info->test_suite_name() + "_" + info->name();
    std::replace(name.begin(), name.end(), '/', '_');
    path_ = std::filesystem::path(::testing::TempDir()) / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// A cube of n^3 cells, each split into 6 tets around its main diagonal (Kuhn subdivision, which
/// conforms across cells), with every vertex moved by a random offset of up to 5% of a cell and
/// the whole scaled by an irrational-ish factor. All tets positively oriented.
inline TetMesh make_jittered_cube(int n, unsigned seed = 7) {
  const double h = 0.1234567891 / n;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.05 * h, 0.05 * h);
  TetMesh mesh;
  const int m = n + 1;
  mesh.V.resize(m * m * m, 3);
  auto id = [m](int i, int j, int k) { return i + m * (j + m * k); };
  for (int k = 0; k < m; ++k) {
    for (int j = 0; j < m; ++j) {
      for (int i = 0; i < m; ++i) {
        mesh.V.row(id(i, j, k)) << i * h + jitter(rng), j * h + jitter(rng), k * h + jitter(rng);
      }
    }
  }
  mesh.T.resize(6 * n * n * n, 4);
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  int t = 0;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        for (const auto& p : perms) {
          int c[3] = {0, 0, 0};
          int row[4];
          row[0] = id(i, j, k);
          for (int s = 0; s < 3; ++s) {
            c[p[s]] = 1;
            row[s + 1] = id(i + c[0], j + c[1], k + c[2]);
          }
          mesh.T.row(t++) << row[0], row[1], row[2], row[3];
        }
      }
    }
  }
  orient_tets_positively(mesh);
  return mesh;
}

/// Bitwise equality, so -0.0 vs 0.0 and NaN payloads count.
inline bool bit_equal(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The message of the InputError `f` throws, or "" (and a test failure) if it throws none.
template <class F>
std::string input_error_message(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

}  // namespace rbaa::test
