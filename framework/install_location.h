#pragma once
// Where ROME's data (robots/) is, found at run time from where ROME's shared library librome_location.so is, so an
// install works wherever `cmake --install --prefix` put it and wherever it was moved afterwards:
//   <folder of librome_location.so>/<libdir-to-datadir>/rome
// where <libdir-to-datadir> is the relative path from the install's library folder to its data folder, fixed at
// configure time (usually ../share). The build tree has the same layout (build/lib/, build/share/rome/robots linking
// to the source tree's robots/), so a build and an install find their data the same way. No absolute path of the
// machine that built ROME is compiled in.

#include <string>

namespace rome {

/// The data folder of the ROME this program runs with (see above). Empty if the library's own location cannot be
/// read (dladdr failed), which does not happen for a library loaded from a file.
std::string InstalledDataFolder();

}  // namespace rome
