#include <gtest/gtest.h>

#include <cstdio>

#include <algorithm>
#include <limits>

#include "io/io_test_support.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/csv.hpp"
#include "rbaa/io/number_text.hpp"
#include "rbaa/io/text_reader.hpp"

namespace rbaa {
namespace {

using test::input_error_message;
using test::ScratchDir;

std::vector<std::string> files_in(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(AtomicFile, WritesAndLeavesNoTemporaryFile) {
  ScratchDir dir;
  write_file_atomically(dir.file("out.txt"), [](std::ostream& os) { os << "first\n"; });
  write_file_atomically(dir.file("out.txt"), [](std::ostream& os) { os << "second\n"; });
  EXPECT_EQ(test::read_text(dir.file("out.txt")), "second\n");
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, MissingDirectoryFailsClearly) {
  ScratchDir dir;
  const std::string path = dir.file("no/such/dir/out.txt");
  const std::string msg = input_error_message(
      [&] { write_file_atomically(path, [](std::ostream& os) { os << "x"; }); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
  EXPECT_TRUE(files_in(dir.path()).empty());
}

TEST(AtomicFile, AFailingWriterKeepsTheOldFile) {
  ScratchDir dir;
  write_file_atomically(dir.file("keep.txt"), [](std::ostream& os) { os << "old\n"; });
  EXPECT_THROW(write_file_atomically(dir.file("keep.txt"),
                                     [](std::ostream& os) {
                                       os << "partial";
                                       throw std::runtime_error("interrupted");
                                     }),
               std::runtime_error);
  EXPECT_EQ(test::read_text(dir.file("keep.txt")), "old\n");
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"keep.txt"});
}

TEST(AtomicFile, ParentThatIsAFileFailsClearly) {
  ScratchDir dir;
  test::write_text(dir.file("plain"), "x");
  const std::string path = dir.file("plain/out.txt");
  const std::string msg = input_error_message(
      [&] { write_file_atomically(path, [](std::ostream& os) { os << "x"; }); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("Not a directory"), std::string::npos) << msg;
}

// A directory the process may not write into: a read-only one for a normal user; for root (as
// README's set-up runs), which ignores permission bits, /proc/self, where no file can be created.
TEST(AtomicFile, UnwritableDirectoryFailsClearly) {
  ScratchDir dir;
  std::string path = dir.file("ro/out.txt");
  const bool root = ::geteuid() == 0;
  if (root) {
    path = "/proc/self/rbaa-out.txt";
  } else {
    std::filesystem::create_directory(dir.file("ro"));
    std::filesystem::permissions(
        dir.file("ro"), std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  }
  const std::string msg = input_error_message(
      [&] { write_file_atomically(path, [](std::ostream& os) { os << "x"; }); });
  if (!root) std::filesystem::permissions(dir.file("ro"), std::filesystem::perms::owner_all);
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(Csv, RoundTripIsExact) {
  ScratchDir dir;
  Eigen::MatrixXd rows = Eigen::MatrixXd::Random(5, 3);
  rows(0, 0) = 1.0 / 3.0;
  rows(1, 1) = -std::numeric_limits<double>::denorm_min();
  rows(2, 2) = 6.02214076e23;
  write_csv(dir.file("t.csv"), {"a", "b", "c"}, rows);
  const CsvTable table = read_csv(dir.file("t.csv"));
  EXPECT_EQ(table.header, (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_TRUE(test::bit_equal(table.values, rows));
  EXPECT_EQ(table.row_lines, (std::vector<int>{2, 3, 4, 5, 6}));
  EXPECT_EQ(table.column("c"), 2);
  EXPECT_EQ(table.column("d"), -1);
}

TEST(NumberText, ShortestExactForm) {
  EXPECT_EQ(format_double(0.1), "0.1");
  EXPECT_EQ(format_double(2.5e9), "2.5e+09");
  for (double x : {1.0 / 3.0, 6.5e11, -1e-300, std::numeric_limits<double>::max()}) {
    EXPECT_EQ(*parse_double(format_double(x)), x);
  }
  EXPECT_EQ(*parse_double("+1.5"), 1.5);
  EXPECT_FALSE(parse_double("1.5x"));
  EXPECT_FALSE(parse_double(""));
  EXPECT_FALSE(parse_double("1e999"));
  EXPECT_EQ(*parse_int("-42"), -42);
  EXPECT_FALSE(parse_int("4.2"));
  EXPECT_FALSE(parse_int("99999999999999999999"));
}

// Report figures to a few significant digits, as printf's %.4g, whatever the stream's locale.
TEST(NumberText, SignificantDigitsAsPrintfG) {
  for (double x : {0.0, 0.12345678, -0.000123456, 123456.0, 2.5e9, 1.0 / 3.0, 7.3}) {
    char expected[64];
    std::snprintf(expected, sizeof(expected), "%.4g", x);
    EXPECT_EQ(format_significant(x, 4), expected) << x;
  }
  EXPECT_EQ(format_significant(0.6353, 2), "0.64");
}

TEST(TextReader, LineBoundAndStreamReads) {
  TextReader r("mem.txt", "# c\n1 2 # tail\n\n  3\nword with spaces  \n");
  r.set_comment_char('#');
  ASSERT_TRUE(r.next_line());
  EXPECT_EQ(r.line(), 2);
  EXPECT_EQ(r.read_int("a"), 1);
  EXPECT_EQ(r.read_int("b"), 2);
  EXPECT_FALSE(r.has_word());
  EXPECT_EQ(r.read_int_anywhere("c"), 3);
  EXPECT_EQ(r.line(), 4);
  ASSERT_TRUE(r.next_line());
  EXPECT_EQ(r.rest_of_line(), "word with spaces");
  EXPECT_FALSE(r.next_line());
  const std::string msg = input_error_message([&] { r.read_word_anywhere("more"); });
  EXPECT_EQ(msg, "mem.txt:5: unexpected end of file while reading more (file truncated?)");
}

}  // namespace
}  // namespace rbaa
