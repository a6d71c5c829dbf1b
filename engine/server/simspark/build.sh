#!/bin/bash
# Builds SimSpark (spark) and rcssserver3d headless into $PREFIX.
#
# Run by `libero server install --server simspark` with:
#   SRC     a source tree holding spark/ and rcssserver3d/ side by side (a copy: it is patched)
#   PREFIX  the install prefix (inside the per-user cache, never the checkout)
#   JOBS    parallel make jobs
# Two patches, both for a headless loopback-only server:
#   - spark/plugin/CMakeLists.txt adds the Qt plugins unconditionally; without Qt5 they fail to
#     configure, so they are guarded with if (Qt5_FOUND).
#   - netcontrol.cpp binds INADDR_ANY; the agent and monitor ports are bound to 127.0.0.1 instead.
set -euo pipefail
: "${SRC:?}" "${PREFIX:?}" "${JOBS:=2}"

plugins="$SRC/spark/plugin/CMakeLists.txt"
for plugin in inputqt openglsysqt; do
    sed -i "s|^add_subdirectory($plugin)\$|if (Qt5_FOUND)\n  add_subdirectory($plugin)\nendif (Qt5_FOUND)|" "$plugins"
done
grep -q "if (Qt5_FOUND)" "$plugins"

netcontrol="$SRC/spark/lib/oxygen/simulationserver/netcontrol.cpp"
sed -i 's|mLocalAddr  = Addr(INADDR_ANY, INADDR_ANY);|mLocalAddr  = Addr(INADDR_ANY, INADDR_LOOPBACK);|' "$netcontrol"
grep -q "INADDR_LOOPBACK" "$netcontrol"

echo "== spark: configure"
mkdir -p "$SRC/spark/build"
cd "$SRC/spark/build"
cmake .. -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$PREFIX" -DBUILD_CARBON=OFF \
    -DCMAKE_INSTALL_RPATH="$PREFIX/lib/simspark;$PREFIX/lib/rcssserver3d" -Wno-dev
echo "== spark: build"
make -j"$JOBS"
make install

echo "== rcssserver3d: configure"
mkdir -p "$SRC/rcssserver3d/build"
cd "$SRC/rcssserver3d/build"
cmake .. -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$PREFIX" \
    -DCMAKE_PREFIX_PATH="$PREFIX" -DSPARK_DIR="$PREFIX" \
    -DCMAKE_INSTALL_RPATH="$PREFIX/lib/simspark;$PREFIX/lib/rcssserver3d" -Wno-dev
echo "== rcssserver3d: build"
make -j"$JOBS"
make install
echo "== done: $PREFIX/bin/rcssserver3d"
