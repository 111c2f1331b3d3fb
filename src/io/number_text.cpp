#include "rbaa/io/number_text.hpp"

#include <charconv>
#include <system_error>

namespace rbaa {

std::string format_double(double x) {
  // 32 characters hold the longest shortest-round-trip form ("-2.2250738585072014e-308").
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), x);
  return std::string(buffer, result.ptr);
}

std::string format_significant(double x, int digits) {
  char buffer[64];
  const auto result =
      std::to_chars(buffer, buffer + sizeof(buffer), x, std::chars_format::general, digits);
  return std::string(buffer, result.ptr);
}

void write_double(std::ostream& os, double x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), x);
  os.write(buffer, result.ptr - buffer);
}

namespace {

// from_chars rejects a leading '+', which other tools (and people) do write.
std::string_view strip_plus(std::string_view text) {
  if (text.size() > 1 && text[0] == '+' && text[1] != '-' && text[1] != '+') text.remove_prefix(1);
  return text;
}

}  // namespace

std::optional<double> parse_double(std::string_view text) {
  text = strip_plus(text);
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  // Out-of-range magnitudes ("1e999") are reported as errors rather than silently saturated.
  if (result.ec != std::errc() || result.ptr != text.data() + text.size()) return std::nullopt;
  return value;
}

std::optional<long long> parse_int(std::string_view text) {
  text = strip_plus(text);
  if (text.empty()) return std::nullopt;
  long long value = 0;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
  if (result.ec != std::errc() || result.ptr != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace rbaa
