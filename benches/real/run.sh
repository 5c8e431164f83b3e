#!/usr/bin/env bash
# Bitterli's pbrt-v4 scenes (../shared/data/bitterli/) against their Tungsten references.
#
#   benches/real/run.sh [SECONDS] [OUT]     (defaults: 20 s per scene, target/real)
#
# Each scene renders at a quarter of its reference's resolution for SECONDS with 2 threads and the integrator its file asks for
# (as Prism imports it). The reference is box-filtered to the same size by `prism compare`. Writes OUT/table.md
# (mean ratio per channel, relMSE, RMSE, set-up time, peak memory, warnings) and OUT/NAME.png beside
# OUT/NAME-reference.png. Scenes whose files are incomplete in the source (see the data's MANIFEST.md) are listed
# with their error.
set -euo pipefail
cd "$(dirname "$0")/../.."
SECONDS_PER_SCENE=${1:-20}
OUT=${2:-target/real}
DATA=../shared/data/bitterli
mkdir -p "$OUT"
cargo build --release -q --bin prism
P=target/release/prism
TABLE="$OUT/table.md"
{
  echo "| scene | size | mean ratio (R, G, B) | relMSE | RMSE | set-up s | samples/px | peak MB | warnings |"
  echo "|---|---|---|---:|---:|---:|---:|---:|---|"
} > "$TABLE"
for dir in "$DATA"/*/; do
  name=$(basename "$dir")
  scene="$dir/scene-v4.pbrt"
  ref="$dir/TungstenRender.exr"
  [ -f "$scene" ] && [ -f "$ref" ] || continue
  # A quarter of the reference's resolution (the files' Film lines are often commented alternatives).
  size=$(python3 - "$ref" <<'PY'
import struct, sys
# The dataWindow attribute of the EXR header: name, type, size, then four int32.
b = open(sys.argv[1], "rb").read(1 << 16)
at = 8
while b[at] != 0:
    name_end = b.index(b"\0", at); name = b[at:name_end]
    type_end = b.index(b"\0", name_end + 1)
    (n,) = struct.unpack_from("<i", b, type_end + 1)
    if name == b"dataWindow":
        x0, y0, x1, y1 = struct.unpack_from("<4i", b, type_end + 5)
        print("%dx%d" % ((x1 - x0 + 1) // 4, (y1 - y0 + 1) // 4)); break
    at = type_end + 5 + n
PY
)
  log="$OUT/$name.log"
  if ! /usr/bin/time -f "peak_kb %M" "$P" render "$scene" --size "$size" --time "$SECONDS_PER_SCENE" --threads 2 \
      -o "$OUT/$name.exr" -o "$OUT/$name.png" > "$log" 2>&1; then
    err=$(grep -m1 '^error:' "$log" | sed 's/|/\\|/g' || true)
    echo "| $name | $size | not rendered: ${err#error: } | | | | | | |" >> "$TABLE"
    continue
  fi
  metrics=$("$P" compare "$OUT/$name.exr" "$ref" --json 2>/dev/null)
  # Fields: the mean ratio per channel, relMSE, RMSE ("n/a" where the reference has a non-finite pixel).
  IFS=$'\t' read -r ratio relmse rmse < <(python3 - "$metrics" <<'PY'
import json, sys
m = json.loads(sys.argv[1])
t, r = m["mean_test"], m["mean_reference"]
f = lambda v, fmt: "n/a" if v is None else fmt % v
ratio = ", ".join("n/a" if a is None or b is None else "%.3f" % (a / b) for a, b in zip(t, r))
print(ratio, f(m["relmse"], "%.4f"), f(m["rmse"], "%.4f"), sep="\t")
PY
)
  setup=$(grep -o '[0-9.]* s setup' "$log" | grep -o '^[0-9.]*' | tail -1)
  spp=$(grep -o '[0-9]* spp' "$log" | grep -o '^[0-9]*' | tail -1)
  peak=$(( $(grep -o 'peak_kb [0-9]*' "$log" | grep -o '[0-9]*$') / 1024 ))
  warnings=$(grep '^warning:' "$log" | grep -v 'output name' | sed 's/^warning: //; s/^[^ ]*\.pbrt: //; s/|/\\|/g' | paste -sd ';' - || true)
  printf '| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n' "$name" "$size" "$ratio" "$relmse" "$rmse" \
    "$setup" "$spp" "$peak" "$warnings" >> "$TABLE"
  python3 - "$ref" "$OUT/$name-reference.png" "$size" <<'PY' || true
import sys
# The reference as a PNG of the same size, for side-by-side viewing (needs the OpenEXR and Pillow modules).
try:
    import OpenEXR, numpy as np
    from PIL import Image
except ImportError:
    sys.exit(0)
with OpenEXR.File(sys.argv[1]) as f:
    ch = f.channels()
    a = np.asarray(ch['RGB'].pixels if 'RGB' in ch else np.stack([ch[c].pixels for c in 'RGB'], -1), dtype=np.float64)
w, h = map(int, sys.argv[3].split('x'))
H, W, _ = a.shape
a = np.nan_to_num(a, nan=0, posinf=0).reshape(h, H // h, w, W // w, 3).mean(axis=(1, 3))
s = np.where(a <= 0.0031308, 12.92 * a, 1.055 * np.power(np.clip(a, 0, None), 1 / 2.4) - 0.055)
Image.fromarray((np.clip(s, 0, 1) * 255 + 0.5).astype(np.uint8)).save(sys.argv[2])
PY
done
cat "$TABLE"
