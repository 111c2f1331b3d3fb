#pragma once
// Numeric CSV tables: a header line of column names, then rows of numbers separated by commas.
// Used for trajectories, progress logs and per-element materials.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace rbaa {

/// A numeric CSV file as read: column names, #rows by #columns values, and the 1-based file line
/// of every row (so callers checking values can name the line at fault).
struct CsvTable {
  std::string path;
  std::vector<std::string> header;
  int header_line = 1;
  Eigen::MatrixXd values;
  std::vector<int> row_lines;

  /// Index of the column called `name`, or -1.
  int column(const std::string& name) const;
};

/// Reads a CSV file with a header line. Fields are trimmed; header names may be double-quoted;
/// blank lines and lines starting with '#' are skipped. Throws InputError "FILE:LINE: ..." on a
/// row with the wrong number of fields, an empty or non-numeric field, or a repeated column name.
/// "nan" and "inf" are read as numbers: callers decide whether they are allowed.
CsvTable read_csv(const std::string& path);

/// Writes `header` and the #rows by header.size() matrix `rows` atomically, every value in its
/// shortest exactly-round-tripping form.
void write_csv(const std::string& path, const std::vector<std::string>& header,
               const Eigen::MatrixXd& rows);

}  // namespace rbaa
