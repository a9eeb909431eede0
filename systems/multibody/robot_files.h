#pragma once
// FindRobotFile: where a robot description named by the user is read from.
//   * an absolute path is used as given (the user named that file);
//   * a relative path whose first component is "." or ".." ("./robots/...", "../my_robot.rome.json") is resolved
//     against the current folder (the user asked for it);
//   * any other relative path ("robots/amber/amber.rome.json") is looked up ONLY under the data folders, in order:
//     $ROME_DATA_DIR, then ROME's own data folder, found relative to ROME's library wherever it is installed or
//     moved (framework/install_location.h: <prefix>/share/rome once installed, <build>/share/rome in a build tree).
//     There is no other fallback (not the source tree). Never in the current folder: a file planted in a shared
//     working folder (such as the temporary directory) is not loaded instead of ROME's own.
// When nothing matches, the error names every place it looked and how to name a file in the current folder.

#include <string>
#include <vector>

namespace rome {

/// The file to read for `path` (see above); std::runtime_error listing every place tried if a data-folder lookup finds
/// nothing. A path used as given is not checked here: the loader names what is wrong with it.
std::string FindRobotFile(const std::string& path);
/// The data folders tried for a relative path, in order ($ROME_DATA_DIR if set, then InstalledDataFolder()).
std::vector<std::string> RobotDataFolders();

}  // namespace rome
