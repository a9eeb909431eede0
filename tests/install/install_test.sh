#!/usr/bin/env bash
# The install as a user gets it: `cmake --install --prefix` into one folder, then the whole prefix MOVED to another
# (the install must be relocatable), and two outside projects built against the moved copy:
#   tests/install/app       find_package(rome), rome::rome: walks AMBER 3 steps and uses a symbol of every library;
#   tests/install/core_app  find_package(rome COMPONENTS core), rome::core: must link no Ipopt, Bullet or urdfdom;
#   tests/install/snippet_app  the README's C++ example, extracted from README.md: must build and walk;
# and, with ROME_PYTHON=ON, the rome Python module imported from the moved prefix runs a tiny diagram.
# Both run from an unrelated folder, with the source and build trees hidden behind empty mounts (a private mount
# namespace through unshare, where the kernel allows one), and ROME_DATA_DIR unset: the robot must come from the moved
# prefix. Then ROME_DATA_DIR, when set, must win. No installed file may name the source or the build folder.
# usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$(cd "$1" && pwd)"; src="$(cd "$2" && pwd)"
work="$(mktemp -d "${TMPDIR:-/tmp}/rome_install_test.XXXXXX")"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

cmake --install "$build" --prefix "$work/staged/prefix" > "$work/install.log"
mv "$work/staged/prefix" "$work/moved"
prefix="$work/moved"
for f in include/rome/framework/system.h include/rome/framework/install_location.h include/rome/systems/visualization/plot.h \
         include/rome/diagrams/walking/walking_diagram.h include/rome/diagrams/hopping/hopping_diagram.h \
         share/rome/robots/amber/amber.rome.json lib/cmake/rome/romeConfig.cmake lib/cmake/rome/romeCoreTargets.cmake; do
  [ -f "$prefix/$f" ] || fail "$f was not installed"
done
ls "$prefix"/lib*/librome_location.so > /dev/null 2>&1 || ls "$prefix"/lib/*/librome_location.so > /dev/null 2>&1 || fail "librome_location.so was not installed"
if hits="$(grep -rlF -e "$src" -e "$build" "$prefix")"; then fail "installed files name the build machine's folders: $hits"; fi

launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
for app in app core_app; do
  cmake -S "$src/tests/install/$app" -B "$work/$app" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" "${launcher[@]}" \
    > "$work/$app.configure.log" 2>&1 || { cat "$work/$app.configure.log"; fail "$app does not configure"; }
  cmake --build "$work/$app" > "$work/$app.build.log" 2>&1 || { cat "$work/$app.build.log"; fail "$app does not build"; }
done
# The README's C++ example (its first ```cpp block) builds against the install, and walks.
awk '/^```cpp$/ { inside = 1; next } /^```$/ { if (inside) exit } inside' "$src/README.md" > "$work/readme_snippet.cc"
grep -q "int main" "$work/readme_snippet.cc" || fail "README.md has no C++ example with a main"
cmake -S "$src/tests/install/snippet_app" -B "$work/snippet_app" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
  -DSNIPPET="$work/readme_snippet.cc" "${launcher[@]}" > "$work/snippet.configure.log" 2>&1 || { cat "$work/snippet.configure.log"; fail "the README example does not configure"; }
cmake --build "$work/snippet_app" > "$work/snippet.build.log" 2>&1 || { cat "$work/snippet.build.log"; fail "the README example does not build"; }
if ldd "$work/core_app/core_app" | grep -Ei "ipopt|bullet|urdf"; then fail "core_app links a library outside ROME's core"; fi

# Runs "$@" from $work/elsewhere with ROME_DATA_DIR unset and, where allowed, the source and build trees hidden.
mkdir -p "$work/elsewhere"
hidden() {
  if unshare -rm true 2> /dev/null; then
    unshare -rm env -u ROME_DATA_DIR SRC="$src" BUILD="$build" WHERE="$work/elsewhere" bash -c \
      'mount -t tmpfs none "$SRC" && { case "$BUILD" in "$SRC"/*) ;; *) mount -t tmpfs none "$BUILD" ;; esac; } &&
       [ -z "$(ls -A "$SRC")" ] && cd "$WHERE" && exec "$@"' hidden "$@"
  else
    echo "note: no private mount namespace here (unshare refused): the source tree stays visible" >&2
    (cd "$work/elsewhere" && env -u ROME_DATA_DIR "$@")
  fi
}
out="$(hidden "$work/app/app")" || { echo "$out"; fail "app failed"; }
echo "$out"
grep -qxF "robot file: $prefix/share/rome/robots/amber/amber.rome.json" <<< "$out" || fail "the robot did not come from the moved prefix"
out="$(hidden "$work/core_app/core_app")" || { echo "$out"; fail "core_app failed"; }
echo "$out"
out="$(hidden "$work/snippet_app/snippet")" || { echo "$out"; fail "the README example did not walk"; }
echo "README example: $out"
grep -q "^walked: " <<< "$out" || fail "the README example did not walk"

# The Python module (when the build has ROME_PYTHON=ON): imported from the moved prefix with the trees hidden, with the
# interpreter it was built for, it runs a tiny diagram against the closed form and loads a robot from the prefix.
if grep -q "^ROME_PYTHON:BOOL=ON" "$build/CMakeCache.txt"; then
  python="$(sed -n 's/^Python3_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt")"
  init="$(find "$prefix" -path '*/rome/__init__.py' | head -1)"
  [ -n "$init" ] || fail "the rome Python package was not installed"
  pydir="$(dirname "$(dirname "$init")")"
  out="$(hidden env PYTHONPATH="$pydir" PYTHONDONTWRITEBYTECODE=1 "$python" -c '
import math, rome
b = rome.DiagramBuilder()
b.add_system(rome.LinearInvertedPendulumSystem("lip", initial_x=0.1, initial_L=0.0, z0=0.8, gravity=9.81))
d = b.build()
sim = rome.Simulator(d, rome.SimulatorConfig(relative_tolerance=1e-10, absolute_tolerance=1e-12))
sim.advance_to(0.5)
x = d.get_continuous_state(sim.context)[0]
expected = 0.1 * math.cosh(math.sqrt(9.81 / 0.8) * 0.5)
assert abs(x - expected) < 1e-8, (x, expected)
params = rome.SteppingStonesDiagramParams.for_robot("robots/amber/amber.rome.json")
print("python: module", rome.__file__, "x(0.5 s) =", x)
')" || { echo "$out"; fail "the installed Python module failed"; }
  echo "$out"
  grep -qF "python: module $pydir/rome/__init__.py" <<< "$out" || fail "the Python module did not come from the moved prefix"
fi

# An explicit ROME_DATA_DIR wins over the installed data.
mkdir -p "$work/own/robots"
cp -r "$prefix/share/rome/robots/amber" "$work/own/robots/"
out="$(cd "$work/elsewhere" && ROME_DATA_DIR="$work/own" "$work/app/app")" || { echo "$out"; fail "app with ROME_DATA_DIR failed"; }
grep -qxF "robot file: $work/own/robots/amber/amber.rome.json" <<< "$out" || fail "ROME_DATA_DIR did not win: $out"
echo "install test: ok (prefix moved, trees hidden, ROME_DATA_DIR wins)"
