#!/usr/bin/env bash
# `prism watch`'s restart latency on a 1M-triangle scene: the time from a save to the first pass of the new render,
# as the watcher prints it, for three edits of each kind: the camera, a material, the mesh file saved unchanged
# (read again, accelerator reused), the mesh's geometry changed (read again, accelerator built). Needs numpy.
#   benches/watch/latency.sh [PRISM_BINARY]
set -euo pipefail
prism=$(realpath "${1:-target/release/prism}")
here=$(cd "$(dirname "$0")" && pwd)
dir=$(mktemp -d)
trap 'kill $pid 2>/dev/null || true; rm -rf "$dir"' EXIT
python3 "$here/grid.py" 0.05 "$dir/grid.ply"
cat > "$dir/scene.ron" <<'RON'
(
    camera: (eye: (0, 1.5, 2.5), target: (0, 0, 0), up: (0, 1, 0), fov: 40, size: (128, 96)),
    render: (integrator: envlight, spp: 16),
    materials: { "m": Lambert(albedo: (0.7, 0.7, 0.7)) },
    entities: [(shape: Mesh(path: "grid.ply"), material: "m"), (light: Environment(radiance: (1, 1, 1)))],
)
RON
"$prism" watch "$dir/scene.ron" --port 0 2> "$dir/log" &
pid=$!
until grep -q "done" "$dir/log"; do sleep 0.2; done
edit() { sed -i "$1" "$dir/scene.ron"; sleep 2; }
for _ in 1 2 3; do edit 's/eye: (0, 1.5/eye: (0.3, 1.5/'; edit 's/eye: (0.3, 1.5/eye: (0, 1.5/'; done
for _ in 1 2 3; do edit 's/0.7, 0.7, 0.7/0.7, 0.2, 0.2/'; edit 's/0.7, 0.2, 0.2/0.7, 0.7, 0.7/'; done
for _ in 1 2 3; do touch "$dir/grid.ply"; sleep 3; done
for a in 0.06 0.07 0.05; do python3 "$here/grid.py" $a "$dir/grid.ply"; sleep 5; done
grep "reloaded" "$dir/log" | awk -v kinds="camera camera camera camera camera camera material material material material material material unchanged-mesh unchanged-mesh unchanged-mesh new-geometry new-geometry new-geometry" \
    'BEGIN { split(kinds, k, " ") } { print k[NR] ": " $0 }'
