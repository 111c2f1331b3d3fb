#pragma once
// Numbers as text, independent of the C++ locale. Doubles are written in the shortest form that
// reads back to the same bits (std::to_chars), so every rbaa file round-trips exactly and stays
// as short as the value allows.

#include <optional>
#include <ostream>
#include <string>
#include <string_view>

namespace rbaa {

/// Shortest decimal text that parses back to exactly `x` ("0.1", "1e-300", "inf", "nan").
std::string format_double(double x);

/// `x` to `digits` significant digits, as printf's %.*g ("0.1235", "1.235e+05"), for reports.
std::string format_significant(double x, int digits);

/// Writes format_double(x) to `os` without going through the stream's precision or locale.
void write_double(std::ostream& os, double x);

/// Stream manipulator for the same: `os << exact(x)`.
struct ExactDouble {
  double value;
};
inline ExactDouble exact(double x) { return {x}; }
inline std::ostream& operator<<(std::ostream& os, ExactDouble x) {
  write_double(os, x.value);
  return os;
}

/// Parses the whole of `text` as a double (a leading '+' is accepted); nullopt if any character
/// is left over or the text is no number.
std::optional<double> parse_double(std::string_view text);

/// Parses the whole of `text` as a base-10 integer (a leading '+' is accepted); nullopt on
/// anything else, including overflow.
std::optional<long long> parse_int(std::string_view text);

}  // namespace rbaa
