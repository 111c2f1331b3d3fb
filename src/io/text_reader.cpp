#include "rbaa/io/text_reader.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rbaa/error.hpp"
#include "rbaa/io/number_text.hpp"

namespace rbaa {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }


}  // namespace

std::string read_whole_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(path + ": cannot read: is a directory");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot read: " + std::strerror(errno));
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw InputError(path + ": cannot read: I/O error");
  return content.str();
}

TextReader::TextReader(const std::string& path) : name_(path), content_(read_whole_file(path)) {
  split_lines();
}

TextReader::TextReader(std::string name, std::string content)
    : name_(std::move(name)), content_(std::move(content)) {
  split_lines();
}

void TextReader::split_lines() {
  std::string_view all(content_);
  std::size_t start = 0;
  while (start < all.size()) {
    std::size_t end = all.find('\n', start);
    if (end == std::string_view::npos) end = all.size();
    std::string_view line = all.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines_.push_back(line);
    start = end + 1;
  }
}

void TextReader::set_comment_char(char comment) { comment_ = comment; }

bool TextReader::line_is_blank(std::string_view line) const {
  for (char c : line) {
    if (comment_ != '\0' && c == comment_) return true;
    if (!is_blank(c)) return false;
  }
  return true;
}

bool TextReader::next_line() {
  const int n = static_cast<int>(lines_.size());
  while (index_ < n) {
    ++index_;
    column_ = 0;
    if (index_ < n && !line_is_blank(lines_[index_])) return true;
  }
  return false;
}

void TextReader::expect_next_line(const std::string& what) {
  if (!next_line()) fail_end_of_file(what);
}

int TextReader::line() const {
  const int n = static_cast<int>(lines_.size());
  if (n == 0) return 1;
  if (index_ < 0) return 1;
  return index_ < n ? index_ + 1 : n;
}

bool TextReader::on_unterminated_last_line() const {
  return index_ >= 0 && index_ + 1 == static_cast<int>(lines_.size()) && !content_.empty() &&
         content_.back() != '\n';
}

void TextReader::skip_blanks() {
  if (index_ < 0 || index_ >= static_cast<int>(lines_.size())) return;
  const std::string_view line = lines_[index_];
  while (column_ < line.size() && is_blank(line[column_])) ++column_;
  if (comment_ != '\0' && column_ < line.size() && line[column_] == comment_) column_ = line.size();
}

bool TextReader::has_word() {
  if (index_ < 0 || index_ >= static_cast<int>(lines_.size())) return false;
  skip_blanks();
  return column_ < lines_[index_].size();
}

std::string_view TextReader::read_word(const std::string& what) {
  if (index_ < 0) expect_next_line(what);
  if (!has_word()) {
    if (index_ >= static_cast<int>(lines_.size())) fail_end_of_file(what);
    fail("expected " + what + ", but the line ends");
  }
  const std::string_view line = lines_[index_];
  const std::size_t start = column_;
  while (column_ < line.size() && !is_blank(line[column_]) &&
         !(comment_ != '\0' && line[column_] == comment_)) {
    ++column_;
  }
  return line.substr(start, column_ - start);
}

std::string_view TextReader::peek_word() {
  if (!has_word()) return {};
  const std::size_t saved = column_;
  const std::string_view word = read_word("a word");
  column_ = saved;
  return word;
}

std::string_view TextReader::read_word_anywhere(const std::string& what) {
  while (!has_word()) expect_next_line(what);
  return read_word(what);
}

std::string_view TextReader::rest_of_line() {
  if (!has_word()) return {};
  std::string_view rest = lines_[index_].substr(column_);
  if (comment_ != '\0') rest = rest.substr(0, rest.find(comment_));
  while (!rest.empty() && is_blank(rest.back())) rest.remove_suffix(1);
  column_ = lines_[index_].size();
  return rest;
}

void TextReader::expect_line_end(const std::string& what) {
  if (has_word()) {
    const std::string extra(read_word("a word"));
    fail("unexpected " + quote(extra) + " after " + what);
  }
}

double TextReader::to_double(std::string_view word, const std::string& what) const {
  const auto value = parse_double(word);
  if (!value) fail("expected " + what + " (a number), found " + quote(word));
  return *value;
}

long long TextReader::to_int(std::string_view word, const std::string& what) const {
  const auto value = parse_int(word);
  if (!value) fail("expected " + what + " (an integer), found " + quote(word));
  return *value;
}

double TextReader::read_double(const std::string& what) { return to_double(read_word(what), what); }

long long TextReader::read_int(const std::string& what) { return to_int(read_word(what), what); }

int TextReader::read_count(const std::string& what, long long max_count) {
  const long long n = read_int(what);
  if (n < 0) fail(what + " is negative (" + std::to_string(n) + ")");
  if (n > max_count) {
    fail(what + " is " + std::to_string(n) + ", more than the " + std::to_string(max_count) +
         " this reader accepts");
  }
  return static_cast<int>(n);
}

double TextReader::read_double_anywhere(const std::string& what) {
  return to_double(read_word_anywhere(what), what);
}

long long TextReader::read_int_anywhere(const std::string& what) {
  return to_int(read_word_anywhere(what), what);
}

void TextReader::fail(const std::string& message) const { fail_at(line(), message); }

void TextReader::fail_at(int line, const std::string& message) const {
  throw InputError(name_ + ":" + std::to_string(line) + ": " + message);
}

void TextReader::fail_end_of_file(const std::string& what) const {
  fail_at(lines_.empty() ? 1 : static_cast<int>(lines_.size()),
          "unexpected end of file while reading " + what + " (file truncated?)");
}

std::string TextReader::quote(std::string_view word) {
  constexpr std::size_t kMaxShown = 40;
  std::string shown = "'";
  for (std::size_t i = 0; i < word.size() && i < kMaxShown; ++i) {
    const unsigned char c = static_cast<unsigned char>(word[i]);
    shown += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (word.size() > kMaxShown) shown += "...";
  return shown + "'";
}

}  // namespace rbaa
