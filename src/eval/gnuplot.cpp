#include "rbaa/eval/gnuplot.hpp"

#include <cstdlib>
#include <filesystem>

namespace rbaa {

std::string gnuplot_quoted(const std::string& text) {
  std::string q;
  for (char c : text) {
    q += c;
    if (c == '\'') q += '\'';
  }
  return q;
}

std::string render_gnuplot(const std::string& stem) {
  const std::filesystem::path path(stem);
  const std::string dir = path.parent_path().string();
  const std::string command = "cd '" + (dir.empty() ? std::string(".") : dir) + "' && gnuplot '" +
                              path.filename().string() + ".gp' >/dev/null 2>&1";
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0 || std::system(command.c_str()) != 0) {
    return "";
  }
  return stem + ".png";
}

}  // namespace rbaa
