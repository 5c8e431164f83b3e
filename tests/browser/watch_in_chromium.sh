#!/usr/bin/env bash
# `prism watch` in a real browser (run by .ci/run): installs Debian's chromium with apt-get if it is missing, then
# watch_in_chromium.py edits a scene under a running `prism watch` and checks the viewer page follows (the colour
# change, the error line, the recovery, the pixel readout, a clean console). Leaves the viewer's screenshot at
# target/watch/screenshot.png (the live-authoring page's picture is a copy of it).
#   tests/browser/watch_in_chromium.sh [PRISM_BINARY]
set -euo pipefail
cd "$(dirname "$0")/../.."
prism=${1:-target/release/prism}
if ! command -v chromium >/dev/null 2>&1; then
    echo "watch_in_chromium: installing Debian's chromium"
    sudo=""
    if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
    $sudo apt-get update -qq
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi
mkdir -p target/watch
python3 tests/browser/watch_in_chromium.py "$prism" --screenshot target/watch/screenshot.png
