#!/bin/sh
# The standing team as an external team, RoboCup start-script style: `start.sh HOST PORT`.
# `libero match --away-cmd tools/teams/standing/start.sh` runs it; LIBERO names the binary
# (default: `libero` on the PATH) and PLAYERS the team size (default 7).
here=$(dirname "$0")
exec "${LIBERO:-libero}" team --host "$1" --port "$2" --team "${TEAM:-Standing}" \
    --players "${PLAYERS:-7}" --behaviors "$here/behaviors" --no-watch
