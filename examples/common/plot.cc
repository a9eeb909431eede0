#include "examples/common/plot.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>

namespace rome::examples {

namespace {
std::string Quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += (c == '"' ? std::string("\\\"") : std::string(1, c));
  return out + "\"";
}
}  // namespace

bool WritePlot(const PlotSpec& spec, const std::string& png_path, std::string* error) { return WritePanels({spec}, png_path, error); }

bool WritePanels(const std::vector<PlotSpec>& panels, const std::string& png_path, std::string* error) {
  namespace fs = std::filesystem;
  if (panels.empty()) {
    if (error) *error = "no panels to plot for " + png_path;
    return false;
  }
  const fs::path data = fs::path(png_path).replace_extension(".plotdata");
  const fs::path script = fs::path(png_path).replace_extension(".gp");
  {
    std::ofstream d(data);
    if (!d) {
      if (error) *error = "cannot write " + data.string();
      return false;
    }
    d << std::setprecision(10);
    for (const PlotSpec& spec : panels)
      for (const Series& s : spec.series) {
        for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) d << s.x[i] << " " << s.y[i] << "\n";
        d << "\n\n";  // gnuplot data block separator (index)
      }
  }
  {
    std::ofstream g(script);
    int height = 0;
    for (const PlotSpec& spec : panels) height += spec.height_px;
    g << "set terminal pngcairo size " << panels[0].width_px << "," << height << " noenhanced\n";
    g << "set output " << Quote(png_path) << "\n";
    // Stacked panels share their left and right margins, so that their time axes line up.
    if (panels.size() > 1) g << "set multiplot layout " << panels.size() << ",1\nset lmargin at screen 0.09\nset rmargin at screen 0.74\n";
    size_t index = 0;
    for (const PlotSpec& spec : panels) {
      g << "set title " << Quote(spec.title) << "\nset xlabel " << Quote(spec.xlabel) << "\nset ylabel " << Quote(spec.ylabel) << "\n";
      g << "set grid\nset key outside right\n";
      g << (spec.equal_axes ? "set size ratio -1\n" : "set size noratio\n");
      g << "plot ";
      for (size_t i = 0; i < spec.series.size(); ++i, ++index)
        g << (i ? ", " : "") << Quote(data.string()) << " index " << index << " with " << spec.series[i].style << " title " << Quote(spec.series[i].title);
      g << "\n";
    }
    if (panels.size() > 1) g << "unset multiplot\n";
  }
  const std::string cmd = "gnuplot " + Quote(script.string()) + " 2>/dev/null";
  const int rc = std::system(cmd.c_str());
  fs::remove(data);
  fs::remove(script);
  if (rc != 0) {
    if (error) *error = "gnuplot failed (exit " + std::to_string(rc) + ") for " + png_path + "; is gnuplot installed (./rome setup)?";
    return false;
  }
  return true;
}

}  // namespace rome::examples
