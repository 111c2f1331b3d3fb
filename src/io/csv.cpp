#include "rbaa/io/csv.hpp"

#include <algorithm>

#include "rbaa/error.hpp"
#include "rbaa/io/atomic_file.hpp"
#include "rbaa/io/number_text.hpp"
#include "rbaa/io/text_reader.hpp"

namespace rbaa {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

}  // namespace

int CsvTable::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  return it == header.end() ? -1 : static_cast<int>(it - header.begin());
}

CsvTable read_csv(const std::string& path) {
  TextReader reader(path);
  reader.set_comment_char('#');
  CsvTable table;
  table.path = path;
  reader.expect_next_line("the header line of column names");
  table.header_line = reader.line();
  for (std::string_view name : split_fields(reader.rest_of_line())) {
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') {
      name = name.substr(1, name.size() - 2);
    }
    if (name.empty()) reader.fail("empty column name in the header line");
    if (table.column(std::string(name)) >= 0) {
      reader.fail("column '" + std::string(name) + "' appears twice in the header line");
    }
    table.header.emplace_back(name);
  }
  const int num_columns = static_cast<int>(table.header.size());
  std::vector<double> values;
  while (reader.next_line()) {
    const std::vector<std::string_view> fields = split_fields(reader.rest_of_line());
    if (static_cast<int>(fields.size()) != num_columns) {
      reader.fail("row has " + std::to_string(fields.size()) + " fields but the header names " +
                  std::to_string(num_columns) + " columns");
    }
    for (int c = 0; c < num_columns; ++c) {
      if (fields[c].empty()) reader.fail("column '" + table.header[c] + "' is empty");
      values.push_back(reader.to_double(fields[c], "a value of column '" + table.header[c] + "'"));
    }
    table.row_lines.push_back(reader.line());
  }
  const int num_rows = static_cast<int>(table.row_lines.size());
  table.values.resize(num_rows, num_columns);
  for (int r = 0; r < num_rows; ++r) {
    for (int c = 0; c < num_columns; ++c) table.values(r, c) = values[r * num_columns + c];
  }
  return table;
}

void write_csv(const std::string& path, const std::vector<std::string>& header,
               const Eigen::MatrixXd& rows) {
  if (rows.cols() != static_cast<Eigen::Index>(header.size())) {
    throw InputError("cannot write " + path + ": " + std::to_string(header.size()) +
                     " column names for " + std::to_string(rows.cols()) + " columns of values");
  }
  for (const std::string& name : header) {
    if (name.find_first_of(",\n\r") != std::string::npos) {
      throw InputError("cannot write " + path + ": column name '" + name +
                       "' contains a comma or a line break");
    }
  }
  write_file_atomically(path, [&](std::ostream& os) {
    for (std::size_t c = 0; c < header.size(); ++c) os << (c ? "," : "") << header[c];
    os << '\n';
    for (Eigen::Index r = 0; r < rows.rows(); ++r) {
      for (Eigen::Index c = 0; c < rows.cols(); ++c) {
        os << (c ? "," : "") << exact(rows(r, c));
      }
      os << '\n';
    }
  });
}

}  // namespace rbaa
