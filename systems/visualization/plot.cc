#include "systems/visualization/plot.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

#include "framework/process.h"
#include "framework/files.h"
#include "framework/text.h"

namespace rome::visualization {

namespace {

// pngcairo's default font: its size [pt] and a generous mean character width at that size [px]; the key's line sample
// and padding [px].
constexpr double kFontPt = 12.0, kCharPx = 8.5, kKeySamplePx = 90.0;

// The gnuplot script: the data inline as datablocks ($s0, $s1, ...: numbers only), every text through GnuplotString,
// the PNG to standard output (no `set output`, so gnuplot opens no file of its own).
std::string GnuplotScript(const std::vector<PlotSpec>& panels) {
  std::ostringstream g;
  g << std::setprecision(10);
  size_t index = 0;
  for (const PlotSpec& spec : panels)
    for (const Series& s : spec.series) {
      g << "$s" << index++ << " << EOD\n";
      for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) g << s.x[i] << " " << s.y[i] << "\n";
      g << "EOD\n";
    }
  int height = 0;
  size_t longest_key = 0;  // [characters] the longest series title of any panel
  for (const PlotSpec& spec : panels) {
    height += spec.height_px;
    for (const Series& s : spec.series) longest_key = std::max(longest_key, s.title.size());
  }
  const int width = panels[0].width_px;
  g << "set terminal pngcairo size " << width << "," << height << " noenhanced\n";
  // Stacked panels share their left and right margins, so that their time axes line up; the right margin leaves room
  // for the longest key entry (the line sample and its text), so that no legend is cut at the image's edge.
  const double key_px = kCharPx * static_cast<double>(longest_key) + kKeySamplePx;
  const double right = std::clamp(1.0 - key_px / width, 0.5, 0.8);  // [fraction of the width] the plot area's right
  if (panels.size() > 1)
    g << "set multiplot layout " << panels.size() << ",1\nset lmargin at screen 0.09\nset rmargin at screen " << right
      << "\n";
  // gnuplot centres a title over the plot area: it fits if it spans at most twice the distance from that centre to
  // the nearer image edge; a longer one is drawn in a smaller font instead of being cut.
  const double centre = 0.5 * (0.09 + right) * width, title_room = 2.0 * std::min(centre, width - centre) - 10.0;
  index = 0;
  for (const PlotSpec& spec : panels) {
    const double title_px = kCharPx * static_cast<double>(spec.title.size());
    g << "set title " << GnuplotString(spec.title);
    if (title_px > title_room)
      g << " font \"," << std::max(7, static_cast<int>(kFontPt * title_room / title_px)) << "\"";
    else
      g << " font \"\"";  // the terminal's font (a title font set for an earlier panel stays otherwise)
    g << "\nset xlabel " << GnuplotString(spec.xlabel) << "\nset ylabel " << GnuplotString(spec.ylabel) << "\n";
    g << "set grid\nset key outside right\n";
    g << (spec.equal_axes ? "set size ratio -1\n" : "set size noratio\n");
    g << "plot ";
    for (size_t i = 0; i < spec.series.size(); ++i, ++index)
      g << (i ? ", " : "") << "$s" << index << " with " << spec.series[i].style << " title "
        << GnuplotString(spec.series[i].title);
    g << "\n";
  }
  if (panels.size() > 1) g << "unset multiplot\n";
  return g.str();
}

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

}  // namespace

bool WritePlot(const PlotSpec& spec, const std::string& png_path, std::string* error) {
  return WritePanels({spec}, png_path, error);
}

bool WritePanels(const std::vector<PlotSpec>& panels, const std::string& png_path, std::string* error) {
  if (panels.empty()) return Fail(error, "no panels to plot for " + png_path);
  try {
    const TempFolder scratch("rome-plot");
    const std::string script = scratch.File("plot.gp");
    WriteFileAtomically(script, GnuplotScript(panels), "gnuplot script");
    const ProcessResult run = RunProgram({"gnuplot", script});
    if (!run.started) return Fail(error, run.error + "; is gnuplot installed (./rome setup)?");
    if (run.exit_code != 0 || run.out.empty())
      return Fail(error, "gnuplot failed (exit " + std::to_string(run.exit_code) + ": " + Excerpt(run.error, 200) +
                             ") for " + Excerpt(png_path, 200));
    WriteFileAtomically(png_path, run.out, "plot");
  } catch (const std::exception& e) { return Fail(error, e.what()); }
  return true;
}

}  // namespace rome::visualization
