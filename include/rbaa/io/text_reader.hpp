#pragma once
// A cursor over a text file that knows the line it is on, so every parse error can say
// "FILE:LINE: what is wrong" on one line. Line-bound reads (read_word, read_int, ...) never run
// into the next line, which is how counts that are off by one are caught at the right line;
// the *_anywhere reads treat the file as a stream of whitespace-separated words (MEDIT).

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace rbaa {

/// What to reserve for a list a file announces `count` entries of: at most 65536, the rest grown
/// as the entries are read. A count is no promise: a short file claiming 2e9 entries would
/// otherwise ask for gigabytes before its missing lines are noticed.
inline std::size_t announced_capacity(long long count) {
  return static_cast<std::size_t>(count < 0 ? 0 : count < (1 << 16) ? count : (1 << 16));
}

/// The whole file at `path`; throws InputError "PATH: cannot read: REASON" (a folder, a missing
/// or unreadable file, an I/O error).
std::string read_whole_file(const std::string& path);

class TextReader {
 public:
  /// Reads the whole file at `path`; throws InputError "PATH: cannot read (reason)".
  explicit TextReader(const std::string& path);
  /// Reads `content` as if it were a file called `name` (for tests and in-memory text).
  TextReader(std::string name, std::string content);

  /// Words from `comment` to the end of a line are ignored (e.g. '#'); '\0' turns comments off.
  void set_comment_char(char comment);

  /// The file name used in messages.
  const std::string& name() const { return name_; }

  /// Moves to the next line holding something other than blanks and comments; false at the end.
  bool next_line();
  /// Like next_line, but fails with "unexpected end of file while reading WHAT".
  void expect_next_line(const std::string& what);
  /// 1-based number of the current line (the last line once the end is reached).
  int line() const;
  /// True when the current line is the file's last and no line break ends it, which is how a
  /// file cut in the middle of a line ends: its content may be a fragment that still parses.
  bool on_unterminated_last_line() const;

  /// True when the current line has another word.
  bool has_word();
  /// The next word of the current line without consuming it; empty if the line has none.
  std::string_view peek_word();
  /// The next word of the current line; fails "expected WHAT, but the line ends" if none.
  std::string_view read_word(const std::string& what);
  /// The next word, moving to following lines if needed; fails at the end of the file.
  std::string_view read_word_anywhere(const std::string& what);
  /// What is left of the current line, without surrounding blanks (may contain spaces).
  std::string_view rest_of_line();
  /// Fails "unexpected 'X' after WHAT" when the current line has another word.
  void expect_line_end(const std::string& what);

  /// Line-bound numbers: fail "expected WHAT (a number), found 'X'" on a non-numeric word.
  double read_double(const std::string& what);
  long long read_int(const std::string& what);
  /// An int count, failing on negative values and on counts above `max_count`.
  int read_count(const std::string& what, long long max_count = 2000000000LL);
  /// Stream versions of the above.
  double read_double_anywhere(const std::string& what);
  long long read_int_anywhere(const std::string& what);

  /// Converts a word already read; fails at the current line like read_double/read_int.
  double to_double(std::string_view word, const std::string& what) const;
  long long to_int(std::string_view word, const std::string& what) const;

  /// Throws InputError "FILE:LINE: message" at the current line.
  [[noreturn]] void fail(const std::string& message) const;
  /// Throws InputError "FILE:LINE: message" at the given 1-based line.
  [[noreturn]] void fail_at(int line, const std::string& message) const;
  /// Throws "FILE:LINE: unexpected end of file while reading WHAT" at the last line.
  [[noreturn]] void fail_end_of_file(const std::string& what) const;

  /// A word made printable and short for an error message (binary files hold anything).
  static std::string quote(std::string_view word);

 private:
  void split_lines();
  void skip_blanks();
  bool line_is_blank(std::string_view line) const;

  std::string name_;
  std::string content_;
  std::vector<std::string_view> lines_;  // views into content_, without '\r' and '\n'
  int index_ = -1;                       // current line, -1 before the first
  std::size_t column_ = 0;               // position within the current line
  char comment_ = '\0';
};

}  // namespace rbaa
