#!/usr/bin/env bash
# Installs the build into a temporary prefix, builds tests/install/app against it with find_package(rome), and runs it
# from a folder where robots/ does not exist (the robot is found in <prefix>/share/rome).
# usage: install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
for f in include/rome/framework/system.h include/rome/diagrams/stepping_stones/stepping_stones_diagram.h \
         share/rome/robots/amber/amber.rome.json lib/cmake/rome/romeConfig.cmake; do
  [ -f "$work/prefix/$f" ] || { echo "FAIL: $f was not installed"; exit 1; }
done
launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$src/tests/install/app" -B "$work/app" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" "${launcher[@]}" > "$work/configure.log"
cmake --build "$work/app" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
mkdir -p "$work/elsewhere"
cd "$work/elsewhere"
ROME_DATA_DIR="$work/prefix/share/rome" "$work/app/app"
