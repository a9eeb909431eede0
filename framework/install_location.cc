#include "framework/install_location.h"

#include <dlfcn.h>

#include <filesystem>

#ifndef ROME_LIBDIR_TO_DATADIR
#error "ROME_LIBDIR_TO_DATADIR must be defined (framework/CMakeLists.txt)"
#endif

namespace rome {

std::string InstalledDataFolder() {
  Dl_info info{};
  // The address of this function lies in librome_location.so itself: dladdr names that file, wherever it was loaded
  // from.
  if (dladdr(reinterpret_cast<void*>(&InstalledDataFolder), &info) == 0 || info.dli_fname == nullptr ||
      *info.dli_fname == '\0')
    return {};
  std::error_code ec;
  std::filesystem::path library(info.dli_fname);
  if (const std::filesystem::path resolved = std::filesystem::weakly_canonical(library, ec); !ec) library = resolved;
  return (library.parent_path() / ROME_LIBDIR_TO_DATADIR / "rome").lexically_normal().string();
}

}  // namespace rome
