#pragma once
// Running gnuplot on a script that rbaa wrote beside its data (path_plot, material_sections):
// the picture is optional (gnuplot may be missing), the script and data always stay.

#include <string>

namespace rbaa {

/// Text for a single-quoted gnuplot string: a quote inside is written twice.
std::string gnuplot_quoted(const std::string& text);

/// Runs `stem`.gp with gnuplot in its own folder (the script names `stem`.png and its data by
/// file name). Returns `stem`.png, or "" when gnuplot is missing or fails.
std::string render_gnuplot(const std::string& stem);

}  // namespace rbaa
