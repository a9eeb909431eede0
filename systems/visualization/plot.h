#pragma once
// Plotting through gnuplot (Debian's gnuplot-nox, installed by ./rome setup): PNG files a person looks at.
// A plot that cannot be made (gnuplot missing or failing) returns false with a message; it never aborts a run.

#include <string>
#include <vector>

namespace rome::visualization {

struct Series {
  std::string title;
  std::vector<double> x, y;
  std::string style = "lines";  ///< gnuplot style: lines, points, linespoints, impulses...
};

struct PlotSpec {
  std::string title, xlabel, ylabel;
  std::vector<Series> series;
  bool equal_axes = false;
  int width_px = 900, height_px = 500;
};

/// Writes `png_path`; returns false and fills `error` if gnuplot is missing or fails.
bool WritePlot(const PlotSpec& spec, const std::string& png_path, std::string* error);

/// Writes `panels` stacked top to bottom into one PNG of panels[0]'s width and the sum of their heights (each panel
/// keeps its own title, labels and series). Returns false as WritePlot, and for no panels.
bool WritePanels(const std::vector<PlotSpec>& panels, const std::string& png_path, std::string* error);

}  // namespace rome::visualization
