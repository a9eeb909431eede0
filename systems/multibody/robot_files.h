#pragma once
// FindRobotFile: where a robot description named by the user is read from.
//   1. the path as given, if it names a file (absolute, or relative to the current folder);
//   2. else, for a relative path, under the data folders in order: $ROME_DATA_DIR, the installed data folder
//      (<install prefix>/share/rome, so "robots/amber/amber.rome.json" works from anywhere after `cmake --install`),
//      and the source tree this library was built from.
// A relative path is never resolved against the current folder alone. When nothing matches, the error names every
// place it looked.

#include <string>
#include <vector>

namespace rome {

/// The file to read for `path` (see above); std::runtime_error listing every place tried if there is none.
std::string FindRobotFile(const std::string& path);
/// The data folders tried for a relative path, in order ($ROME_DATA_DIR if set, install, source).
std::vector<std::string> RobotDataFolders();

}  // namespace rome
