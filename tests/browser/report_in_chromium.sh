#!/usr/bin/env bash
# The report page in a real browser (run by .ci/run): renders the small suite (scenes/report/small.ron) with the
# given prism binary into target/report-small/, installs Debian's chromium with apt-get if it is missing, opens the
# page headless (check_page.py: DevTools protocol, fresh profile, no network) and checks that every image loaded,
# every chart has its curves and the console stayed clean. Leaves the full-page screenshot at
# target/report-small/screenshot.png.
#   tests/browser/report_in_chromium.sh [PRISM_BINARY]
set -euo pipefail
cd "$(dirname "$0")/../.."
prism=${1:-target/release/prism}
if ! command -v chromium >/dev/null 2>&1; then
    echo "report_in_chromium: installing Debian's chromium"
    sudo=""
    if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
    $sudo apt-get update -qq
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
fi
out=target/report-small
rm -rf "$out"
"$prism" report scenes/report/small.ron -o "$out"
python3 tests/browser/check_page.py "$out/index.html" --screenshot "$out/screenshot.png" \
    --expect-no-problems --min-images 40 --min-charts 9
